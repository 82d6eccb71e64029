//! Parse + check throughput on generated programs of 10,000, 20,000 and 40,000 lines of ordinary
//! OpenSCAD-style code (modules with children, functions, comprehensions, loops, transforms).
//!
//! The check should stay under 50 ms at 10,000 lines in release and grow linearly; the `parse`
//! group measures the parser alone, so the checker's own share is the difference.

use std::hint::black_box;
use std::path::Path;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use qcsg_sema::{CheckOptions, FileLoader, check_file};

/// Loads nothing: generated programs are self-contained.
struct NoFiles;

impl FileLoader for NoFiles {
    fn load(&self, path: &Path) -> std::io::Result<String> {
        Err(std::io::Error::new(
            std::io::ErrorKind::NotFound,
            path.display().to_string(),
        ))
    }
}

/// One block of about 40 lines; `i` makes every name unique so that scopes grow with the file.
fn block(i: usize, out: &mut String) {
    use std::fmt::Write as _;
    let _ = write!(
        out,
        r#"/// Width of part {i}.
width_{i} = 10 + {i} % 7;
height_{i} = width_{i} * 2;
offsets_{i} = [for (k = [0 : 3]) [k * width_{i}, 0, 0]];

/// Area of a ring of part {i}.
function ring_area_{i}(r_outer, r_inner = 1) = PI * (r_outer * r_outer - r_inner * r_inner);
function sum_{i}(v, n = 0) = n >= len(v) ? 0 : v[n] + sum_{i}(v, n + 1);
scale_{i} = function (x) x * {i} + 1;

module bracket_{i}(size = [10, 4, 2], holes = 2, $fn = 24) {{
    difference() {{
        cube(size, center = true);
        for (h = [0 : holes - 1], side = [-1, 1])
            translate([side * (h + 1) * size.x / (holes + 2), 0, 0])
                cylinder(h = size.z * 2, r = 0.5, center = true);
    }}
}}

module row_{i}(count = 3) {{
    for (j = [0 : count - 1]) {{
        spacing = width_{i} + j;
        translate([j * spacing, 0, 0]) rotate([0, 0, j * 15]) children();
    }}
}}

row_{i}(4) {{
    let (area = ring_area_{i}(height_{i}, 2), total = sum_{i}([1, 2, 3]))
        if (area > total) {{
            bracket_{i}([width_{i}, 4, 2], holes = 3);
        }} else {{
            color("red") sphere(r = scale_{i}(2));
        }}
}}
translate(offsets_{i}[1]) mirror([1, 0, 0]) scale([1, 1, 2]) intersection() {{
    ellipsoid(r = [3, 2, 1]);
    union() {{ cube(2); sphere(1.5); }}
}}

"#
    );
}

fn program(lines: usize) -> String {
    let mut out = String::new();
    let mut i = 0;
    let mut count = 0;
    while count < lines {
        let before = out.len();
        block(i, &mut out);
        count += out[before..].lines().count();
        i += 1;
    }
    out
}

fn bench_check(c: &mut Criterion) {
    let mut group = c.benchmark_group("parse+check");
    group.sample_size(20);
    for lines in [10_000, 20_000, 40_000] {
        let text = program(lines);
        let analysis = check_file(
            "bench.scad",
            text.clone(),
            &CheckOptions::default(),
            &NoFiles,
        );
        assert!(
            !analysis.has_errors(),
            "generated program has errors: {:?}",
            analysis.diagnostics.first()
        );
        group.throughput(Throughput::Bytes(text.len() as u64));
        group.bench_with_input(BenchmarkId::from_parameter(lines), &text, |b, text| {
            b.iter(|| {
                check_file(
                    "bench.scad",
                    black_box(text.clone()),
                    &CheckOptions::default(),
                    &NoFiles,
                )
            });
        });
    }
    group.finish();

    // The parser's share, for comparison: the checker's own cost is the difference.
    let mut group = c.benchmark_group("parse");
    group.sample_size(20);
    for lines in [10_000, 20_000, 40_000] {
        let text = program(lines);
        group.throughput(Throughput::Bytes(text.len() as u64));
        group.bench_with_input(BenchmarkId::from_parameter(lines), &text, |b, text| {
            b.iter(|| qcsg_syntax::parse(black_box(text), qcsg_diag::FileId(0)));
        });
    }
    group.finish();
}

criterion_group!(benches, bench_check);
criterion_main!(benches);
