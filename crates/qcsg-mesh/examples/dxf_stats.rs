//! Time of `read_dxf` and `drawing_region` on large drawings (the numbers in the crate's report):
//! `cargo run --release -p qcsg-mesh --example dxf_stats`.

use std::fmt::Write;
use std::time::Instant;

use qcsg_mesh::{DrawingLimits, DrawingOptions, PolygonLimits, drawing_region, read_dxf};

fn entities(body: &str) -> String {
    format!("  0\nSECTION\n  2\nENTITIES\n{body}  0\nENDSEC\n  0\nEOF\n")
}

fn line(out: &mut String, a: (f64, f64), b: (f64, f64)) {
    let _ = write!(
        out,
        "  0\nLINE\n  8\n0\n 10\n{}\n 20\n{}\n 11\n{}\n 21\n{}\n",
        a.0, a.1, b.0, b.1
    );
}

/// An `n`-gon of LINEs listed in a scrambled order.
fn polygon(n: usize) -> String {
    let p = |i: usize| {
        let a = std::f64::consts::TAU * (i % n) as f64 / n as f64;
        (100.0 * a.cos(), 100.0 * a.sin())
    };
    let mut body = String::new();
    for k in 0..n {
        // A stride coprime to n visits every edge once, out of order.
        let i = (k * 7919) % n;
        line(&mut body, p(i), p(i + 1));
    }
    entities(&body)
}

/// A square plate with a `k × k` grid of round holes, each with an island.
fn plate(k: usize) -> String {
    let s = 10.0 * k as f64;
    let mut body = String::new();
    for (a, b) in [
        ((0.0, 0.0), (s, 0.0)),
        ((s, 0.0), (s, s)),
        ((s, s), (0.0, s)),
        ((0.0, s), (0.0, 0.0)),
    ] {
        line(&mut body, a, b);
    }
    for i in 0..k {
        for j in 0..k {
            let (x, y) = (10.0 * i as f64 + 5.0, 10.0 * j as f64 + 5.0);
            for r in [3.0, 1.0] {
                let _ = write!(body, "  0\nCIRCLE\n  8\n0\n 10\n{x}\n 20\n{y}\n 40\n{r}\n");
            }
        }
    }
    entities(&body)
}

fn main() {
    let cases = [
        ("polygon of LINEs, scrambled", polygon(10_000)),
        ("polygon of LINEs, scrambled", polygon(100_000)),
        ("plate with 10 × 10 holes and islands", plate(10)),
        ("plate with 30 × 30 holes and islands", plate(30)),
        ("plate with 60 × 60 holes and islands", plate(60)),
    ];
    println!("| drawing | entities | read | region | steps |");
    println!("| --- | --- | --- | --- | --- |");
    for (name, text) in cases {
        let start = Instant::now();
        let drawing = read_dxf(
            text.as_bytes(),
            &DrawingOptions::default(),
            &DrawingLimits::default(),
        )
        .expect("reads");
        let read = start.elapsed();
        let start = Instant::now();
        let region = drawing_region(&drawing, &PolygonLimits::default());
        let built = start.elapsed();
        let entities =
            drawing.paths.iter().map(|p| p.edges.len()).sum::<usize>() + drawing.circles.len();
        let steps = match &region {
            Ok(r) => r.steps.len().to_string(),
            Err(e) => format!("{e}"),
        };
        println!("| {name} | {entities} | {read:.2?} | {built:.2?} | {steps} |");
    }
}
