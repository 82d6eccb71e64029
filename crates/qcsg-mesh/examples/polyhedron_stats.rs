//! Cells, widest cell and time of `polyhedron_cells` on large meshes (the numbers in the crate's
//! report): `cargo run --release -p qcsg-mesh --example polyhedron_stats`.

use std::time::Instant;

use glam::DVec3;
use qcsg_mesh::{Mesh, MeshLimits, polyhedron_cells};

/// A bumpy torus of `rows` × `columns` quads, each split in two triangles, clockwise seen from
/// outside.
fn torus(rows: usize, columns: usize, bumps: f64) -> Mesh {
    let mut points = Vec::new();
    for i in 0..rows {
        for j in 0..columns {
            let u = std::f64::consts::TAU * i as f64 / rows as f64;
            let v = std::f64::consts::TAU * j as f64 / columns as f64;
            let r = 1.0 + bumps * (5.0 * u).sin() * (3.0 * v).cos();
            points.push(DVec3::new(
                (3.0 + r * v.cos()) * u.cos(),
                (3.0 + r * v.cos()) * u.sin(),
                r * v.sin(),
            ));
        }
    }
    let index = |i: usize, j: usize| (i % rows) * columns + (j % columns);
    let mut faces = Vec::new();
    for i in 0..rows {
        for j in 0..columns {
            faces.push(vec![index(i, j), index(i + 1, j + 1), index(i + 1, j)]);
            faces.push(vec![index(i, j), index(i, j + 1), index(i + 1, j + 1)]);
        }
    }
    Mesh { points, faces }
}

fn main() {
    for (rows, columns) in [(24, 12), (100, 100), (200, 250)] {
        let mesh = torus(rows, columns, 0.3);
        let start = Instant::now();
        let polyhedron = polyhedron_cells(&mesh, &MeshLimits::default()).unwrap();
        let elapsed = start.elapsed();
        let widest = polyhedron
            .cells
            .iter()
            .map(|c| c.planes.len())
            .max()
            .unwrap_or(0);
        let mean = polyhedron
            .cells
            .iter()
            .map(|c| c.planes.len())
            .sum::<usize>() as f64
            / polyhedron.cells.len().max(1) as f64;
        println!(
            "bumpy torus {rows}x{columns}: {} triangles, {} cells, planes per cell max {widest} mean {mean:.2}, {:.0} ms, warnings {:?}",
            mesh.faces.len(),
            polyhedron.cells.len(),
            elapsed.as_secs_f64() * 1e3,
            polyhedron.warnings
        );
    }
}
