//! Cells, widest cell and time of `polyhedron_cells` on large meshes (the numbers in the crate's
//! report): `cargo run --release -p qcsg-mesh --example polyhedron_stats`; with `--spheres`,
//! only the bumpy spheres, whose poles are fans of thin triangles around one vertex.

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

/// A bumpy sphere of `slices` × `stacks` (the mesh-scale benchmark's surface, its radius between
/// 8 and 12): a latitude-longitude grid with a fan of `slices` thin triangles at each pole,
/// clockwise seen from outside; `2 · slices · (stacks − 1)` triangles.
fn bumpy_sphere(slices: usize, stacks: usize) -> Mesh {
    use std::f64::consts::PI;
    let radius = |theta: f64, phi: f64| {
        10.0 * (1.0 + 0.15 * (5.0 * theta).sin() * (4.0 * phi).sin() + 0.05 * (13.0 * phi).sin())
    };
    let mut points = vec![
        DVec3::new(0.0, 0.0, radius(0.0, 0.0)),
        DVec3::new(0.0, 0.0, -radius(PI, 0.0)),
    ];
    for i in 1..stacks {
        for j in 0..slices {
            let theta = PI * i as f64 / stacks as f64;
            let phi = 2.0 * PI * j as f64 / slices as f64;
            let r = radius(theta, phi);
            // Rounded to f32 as an STL file stores them.
            points.push(DVec3::new(
                f64::from((r * theta.sin() * phi.cos()) as f32),
                f64::from((r * theta.sin() * phi.sin()) as f32),
                f64::from((r * theta.cos()) as f32),
            ));
        }
    }
    let index = |i: usize, j: usize| 2 + (i - 1) * slices + j % slices;
    let mut faces = Vec::new();
    for j in 0..slices {
        faces.push(vec![0, index(1, j + 1), index(1, j)]);
        for i in 1..stacks - 1 {
            let (a, b, c, d) = (
                index(i, j),
                index(i + 1, j),
                index(i + 1, j + 1),
                index(i, j + 1),
            );
            faces.push(vec![a, c, b]);
            faces.push(vec![a, d, c]);
        }
        faces.push(vec![index(stacks - 1, j), index(stacks - 1, j + 1), 1]);
    }
    Mesh { points, faces }
}

fn main() {
    let only_spheres = std::env::args().any(|a| a == "--spheres");
    let tori: &[(usize, usize)] = if only_spheres {
        &[]
    } else {
        &[(24, 12), (100, 100), (200, 250)]
    };
    for &(slices, stacks) in &[(31, 33), (50, 51), (70, 72), (100, 101)] {
        let mesh = bumpy_sphere(slices, stacks);
        let start = Instant::now();
        let polyhedron = polyhedron_cells(&mesh, &MeshLimits::default()).unwrap();
        let elapsed = start.elapsed();
        println!(
            "bumpy sphere {slices}x{stacks}: {} triangles, {} cells, {:.0} ms, warnings {:?}",
            mesh.faces.len(),
            polyhedron.cells.len(),
            elapsed.as_secs_f64() * 1e3,
            polyhedron.warnings
        );
    }
    for &(rows, columns) in tori {
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
