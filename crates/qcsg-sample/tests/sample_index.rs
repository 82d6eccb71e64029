//! The second pass's sample index finds what a brute-force search over all samples finds: a
//! sample of the quadric, on the same side, that covers a ball around a query point with a
//! radius of at most `r`. Checked at radii small enough against the spread of the query points
//! that the index has to coarsen its map of wanted cubes, and with samples far from any query.

mod common;

use common::{Rng, sphere_scene};
use qcsg_quadric::DVec3;
use qcsg_sample::Sample;
use qcsg_sample::subdivide::{SampleIndex, SurfacePoint};

/// A point of the unit sphere (the scene's only quadric) with its outward normal.
fn on_sphere(direction: DVec3) -> SurfacePoint {
    let n = direction.normalize();
    SurfacePoint::new(n, n)
}

fn sample_at(point: SurfacePoint, radius: f64) -> Sample {
    Sample {
        position: point.position,
        normal: point.normal,
        quadric: 0,
        term: 0,
        radius,
        clip_list: 0,
    }
}

/// Query points spread over the sphere, samples around each (some within `r`, some just
/// beyond, some on the far side) and elsewhere; every query is answered like the brute force.
fn check(r: f64, queries: usize, seed: u64) {
    let dnf = sphere_scene();
    let mut rng = Rng::new(seed);
    let centres: Vec<SurfacePoint> = (0..queries).map(|_| on_sphere(rng.direction())).collect();
    let mut samples = Vec::new();
    for c in &centres {
        for _ in 0..2 {
            let offset = rng.direction() * rng.range(0.0, 2.0 * r);
            let radius = rng.range(0.2, 1.0) * r;
            samples.push(sample_at(on_sphere(c.position + offset), radius));
        }
        // The antipode: near in no sense, and facing away.
        samples.push(sample_at(on_sphere(-c.position), r));
    }
    for _ in 0..queries {
        samples.push(sample_at(on_sphere(rng.direction()), r));
    }
    let keys: Vec<(u32, DVec3)> = centres.iter().map(|c| (0, c.position)).collect();
    let index = SampleIndex::new(&dnf, &samples, &keys, r);
    let mut covered = 0;
    for c in &centres {
        // Every query of the second pass lies within `r / 2` of its key point.
        let extent = rng.range(0.0, 0.5) * r;
        let brute = samples
            .iter()
            .any(|s| s.same_side(c.normal) && (s.position - c.position).length() + extent <= r);
        let found = index.cover((0, 0), *c, extent);
        assert_eq!(
            found.is_some(),
            brute,
            "r = {r}: the index and the brute force disagree at {:?}",
            c.position
        );
        if let Some((i, needed)) = found {
            let s = &samples[i as usize];
            let reach = (s.position - c.position).length() + extent;
            assert!(
                s.same_side(c.normal),
                "r = {r}: a sample facing away covers"
            );
            assert!(
                reach <= needed * (1.0 + 1e-12) && needed <= r,
                "r = {r}: sample {i} at {reach} from the ball's rim is given radius {needed}"
            );
            covered += 1;
        }
    }
    assert!(
        covered > queries / 5,
        "r = {r}: too few decisive queries ({covered})"
    );
}

#[test]
fn index_matches_brute_force() {
    // Few query points, so that most cubes of the map stay unwanted.
    for seed in 0..40 {
        check(0.05, 50, seed);
    }
}

#[test]
fn index_matches_brute_force_when_its_map_coarsens() {
    // At r = 1e-4 the query points span 10⁴ fine cubes a side: far more than one map holds.
    check(1e-4, 400, 100);
    check(1e-7, 200, 101);
}
