//! Cells, widest cell and time of `polygon_cells` on large outlines (the numbers in the crate's
//! report): `cargo run --release -p qcsg-mesh --example polygon_stats`.

use std::time::Instant;

use glam::DVec2;
use qcsg_mesh::{PolygonLimits, polygon_cells};

fn star(n: usize, inner: f64, outer: f64) -> Vec<DVec2> {
    (0..n)
        .map(|i| {
            let angle = std::f64::consts::TAU * i as f64 / n as f64;
            let r = if i % 2 == 0 { outer } else { inner };
            DVec2::new(angle.cos(), angle.sin()) * r
        })
        .collect()
}

fn comb(teeth: usize) -> Vec<DVec2> {
    let mut points = vec![DVec2::new(0.0, 0.0), DVec2::new(2.0 * teeth as f64, 0.0)];
    for t in (0..teeth).rev() {
        let x = 2.0 * t as f64;
        points.extend([
            DVec2::new(x + 1.0, 1.0),
            DVec2::new(x + 1.0, 50.0),
            DVec2::new(x, 50.0),
            DVec2::new(x, 1.0),
        ]);
    }
    points
}

fn holes(per_side: usize) -> (Vec<DVec2>, Vec<Vec<usize>>) {
    let side = 3.0 * per_side as f64;
    let mut points = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(side, 0.0),
        DVec2::new(side, side),
        DVec2::new(0.0, side),
    ];
    let mut paths = vec![vec![0, 1, 2, 3]];
    for i in 0..per_side {
        for j in 0..per_side {
            let base = points.len();
            let (x, y) = (1.0 + 3.0 * i as f64, 1.0 + 3.0 * j as f64);
            points.extend([
                DVec2::new(x, y),
                DVec2::new(x + 1.5, y),
                DVec2::new(x + 1.5, y + 1.5),
                DVec2::new(x, y + 1.5),
            ]);
            paths.push((base..base + 4).collect());
        }
    }
    (points, paths)
}

fn main() {
    let one = |points: Vec<DVec2>| {
        let n = points.len();
        (points, vec![(0..n).collect::<Vec<_>>()])
    };
    let cases = [
        ("star 5000 (spikes 50..100)", one(star(5000, 50.0, 100.0))),
        ("star 5000 (spikes 95..100)", one(star(5000, 95.0, 100.0))),
        ("circle 5000", one(star(5000, 100.0, 100.0))),
        ("circle 1e6", one(star(1_000_000, 100.0, 100.0))),
        ("comb 1000 teeth", one(comb(1000))),
        ("100 holes", holes(10)),
        ("10000 holes", holes(100)),
    ];
    for (name, (points, paths)) in cases {
        let start = Instant::now();
        let polygon = polygon_cells(&points, Some(&paths), &PolygonLimits::default()).unwrap();
        let elapsed = start.elapsed();
        let widest = polygon
            .cells
            .iter()
            .map(|c| c.half_planes.len())
            .max()
            .unwrap_or(0);
        let mean = polygon
            .cells
            .iter()
            .map(|c| c.half_planes.len())
            .sum::<usize>() as f64
            / polygon.cells.len().max(1) as f64;
        println!(
            "{name}: {} points, {} cells, half-planes per cell max {widest} mean {mean:.2}, {:.1} ms",
            points.len(),
            polygon.cells.len(),
            elapsed.as_secs_f64() * 1e3
        );
    }
}
