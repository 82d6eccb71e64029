//! Sample counts, distance queries and time of the sampler on the test scenes at three radii.

#[path = "../tests/common/mod.rs"]
mod common;

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use qcsg_sample::sample;

fn scenes(c: &mut Criterion) {
    let scenes = [
        ("sphere", common::sphere_scene()),
        ("three_spheres", common::three_spheres()),
        ("cube_minus_cylinder", common::cube_minus_cylinder()),
        ("cone_slab", common::cone_slab()),
        ("tangent_spheres", common::tangent_spheres()),
        ("far", common::far_scene()),
        ("tiny", common::tiny_scene()),
    ];
    let mut group = c.benchmark_group("sample");
    group.sample_size(10);
    for (name, dnf) in &scenes {
        for relative in [0.05, 0.01, 0.002] {
            let r = relative * common::diagonal(dnf);
            let Ok(once) = sample(dnf, r) else { continue };
            let stats = once.stats;
            eprintln!(
                "{name} r = {relative} diag: {} samples, {} distance queries, {} basic regions, {} unresolved ({} more proven covered)",
                stats.samples,
                stats.subdivision.distance_queries,
                stats.basic_regions,
                stats.subdivision.unresolved + stats.regions.unresolved,
                stats.subdivision.unresolved_covered,
            );
            group.bench_function(format!("{name}/{relative}"), |b| {
                b.iter(|| sample(black_box(dnf), r))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, scenes);
criterion_main!(benches);
