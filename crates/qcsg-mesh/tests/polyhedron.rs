//! `polyhedron_cells` against an independent generalised-winding-number oracle on convex,
//! non-convex and toroidal meshes at several scales and offsets, its cell bounds, and the errors
//! and warnings for bad meshes.

use glam::DVec3;
use qcsg_mesh::{Mesh, MeshError, MeshLimits, Polyhedron, polyhedron_cells};
use qcsg_testkit::Rng;

/// The generalised winding number (van Oosterom–Strackee solid angles over the faces' fans),
/// for faces listed clockwise seen from outside: about 1 inside, 0 outside.
fn winding_number(mesh: &Mesh, p: DVec3) -> f64 {
    let mut total = 0.0;
    for face in &mesh.faces {
        for k in 1..face.len() - 1 {
            let (a, b, c) = (
                mesh.points[face[0]] - p,
                mesh.points[face[k]] - p,
                mesh.points[face[k + 1]] - p,
            );
            let (la, lb, lc) = (a.length(), b.length(), c.length());
            let numerator = a.dot(b.cross(c));
            let denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
            total += 2.0 * numerator.atan2(denominator);
        }
    }
    // Clockwise from outside: the solid angles come out negative inside.
    -total / (4.0 * std::f64::consts::PI)
}

/// The distance from `p` to triangle `a`, `b`, `c`.
fn distance_to_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let n = (b - a).cross(c - a);
    if n.length_squared() > 0.0 {
        let inside = [(a, b), (b, c), (c, a)]
            .iter()
            .all(|&(u, v)| (v - u).cross(p - u).dot(n) >= 0.0);
        if inside {
            return (p - a).dot(n).abs() / n.length();
        }
    }
    [(a, b), (b, c), (c, a)]
        .iter()
        .map(|&(u, v)| {
            let d = v - u;
            let t = if d == DVec3::ZERO {
                0.0
            } else {
                ((p - u).dot(d) / d.length_squared()).clamp(0.0, 1.0)
            };
            (u + d * t - p).length()
        })
        .fold(f64::INFINITY, f64::min)
}

fn distance_to_mesh(mesh: &Mesh, p: DVec3) -> f64 {
    let mut best = f64::INFINITY;
    for face in &mesh.faces {
        for k in 1..face.len() - 1 {
            best = best.min(distance_to_triangle(
                p,
                mesh.points[face[0]],
                mesh.points[face[k]],
                mesh.points[face[k + 1]],
            ));
        }
    }
    best
}

fn check_membership(mesh: &Mesh, samples: usize, seed: u64) -> Polyhedron {
    let polyhedron = polyhedron_cells(mesh, &MeshLimits::default()).expect("a valid mesh");
    let (lo, hi) = mesh_box(mesh);
    let margin = (hi - lo) * 0.1;
    check_membership_in(mesh, &polyhedron, lo - margin, hi + margin, samples, seed);
    polyhedron
}

fn mesh_box(mesh: &Mesh) -> (DVec3, DVec3) {
    mesh.points.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    )
}

/// Checks `samples` random points of the box `[from, to]` against the oracle.
fn check_membership_in(
    mesh: &Mesh,
    polyhedron: &Polyhedron,
    from: DVec3,
    to: DVec3,
    samples: usize,
    seed: u64,
) {
    let (lo, hi) = mesh_box(mesh);
    let size = (hi - lo).max_element();
    let mut rng = Rng::new(seed);
    for _ in 0..samples {
        let p = from + (to - from) * DVec3::new(rng.unit(), rng.unit(), rng.unit());
        if distance_to_mesh(mesh, p) < 1e-7 * size {
            continue;
        }
        let w = winding_number(mesh, p);
        let expected = w > 0.5;
        let containing: Vec<_> = polyhedron.cells.iter().filter(|c| c.contains(p)).collect();
        assert_eq!(
            !containing.is_empty(),
            expected,
            "membership of {p:?} (winding number {w})"
        );
        assert!(
            containing.len() <= 1,
            "{p:?} lies in {} cells",
            containing.len()
        );
        for c in containing {
            assert!(
                c.min.cmple(p).all() && p.cmple(c.max).all(),
                "cell box misses {p:?}"
            );
        }
    }
}

/// A box with OpenSCAD's documented face order (clockwise seen from outside).
fn cuboid(size: DVec3) -> Mesh {
    let points = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
    ]
    .map(|p| DVec3::from_array(p) * size)
    .to_vec();
    let faces = vec![
        vec![0, 1, 2, 3],
        vec![4, 5, 1, 0],
        vec![7, 6, 5, 4],
        vec![5, 6, 2, 1],
        vec![6, 7, 3, 2],
        vec![7, 4, 0, 3],
    ];
    Mesh { points, faces }
}

/// The signed volume times six of faces as given (negative when clockwise seen from outside).
fn volume6(mesh: &Mesh) -> f64 {
    let mut total = 0.0;
    for face in &mesh.faces {
        for k in 1..face.len() - 1 {
            let (a, b, c) = (
                mesh.points[face[0]],
                mesh.points[face[k]],
                mesh.points[face[k + 1]],
            );
            total += a.dot(b.cross(c));
        }
    }
    total
}

fn reversed(mesh: &Mesh) -> Mesh {
    Mesh {
        points: mesh.points.clone(),
        faces: mesh
            .faces
            .iter()
            .map(|f| f.iter().rev().copied().collect())
            .collect(),
    }
}

/// Puts the faces in OpenSCAD's order if they are not.
fn clockwise(mesh: Mesh) -> Mesh {
    if volume6(&mesh) > 0.0 {
        reversed(&mesh)
    } else {
        mesh
    }
}

/// A closed grid surface: `rows` × `columns` quads of `point(i, j)`, wrapping around in both
/// directions (a torus).
fn torus(rows: usize, columns: usize, big: f64, small: f64, bumps: f64) -> Mesh {
    let mut points = Vec::new();
    for i in 0..rows {
        for j in 0..columns {
            let u = std::f64::consts::TAU * i as f64 / rows as f64;
            let v = std::f64::consts::TAU * j as f64 / columns as f64;
            let r = small * (1.0 + bumps * (5.0 * u).sin() * (3.0 * v).cos());
            points.push(DVec3::new(
                (big + r * v.cos()) * u.cos(),
                (big + r * v.cos()) * u.sin(),
                r * v.sin(),
            ));
        }
    }
    let index = |i: usize, j: usize| (i % rows) * columns + (j % columns);
    let mut faces = Vec::new();
    for i in 0..rows {
        for j in 0..columns {
            // Two triangles per quad, so no face is non-planar.
            faces.push(vec![index(i, j), index(i + 1, j), index(i + 1, j + 1)]);
            faces.push(vec![index(i, j), index(i + 1, j + 1), index(i, j + 1)]);
        }
    }
    clockwise(Mesh { points, faces })
}

/// A sphere of `rings` × `segments` with dents: radius `1 + dent · sin(4θ) sin(3φ)`.
fn dented_sphere(rings: usize, segments: usize, dent: f64) -> Mesh {
    let mut points = vec![DVec3::new(0.0, 0.0, 1.0), DVec3::new(0.0, 0.0, -1.0)];
    for i in 1..rings {
        let theta = std::f64::consts::PI * i as f64 / rings as f64;
        for j in 0..segments {
            let phi = std::f64::consts::TAU * j as f64 / segments as f64;
            let r = 1.0 + dent * (4.0 * theta).sin() * (3.0 * phi).sin();
            points.push(
                r * DVec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                ),
            );
        }
    }
    let ring = |i: usize, j: usize| 2 + (i - 1) * segments + j % segments;
    let mut faces = Vec::new();
    for j in 0..segments {
        faces.push(vec![0, ring(1, j), ring(1, j + 1)]);
        faces.push(vec![1, ring(rings - 1, j + 1), ring(rings - 1, j)]);
        for i in 1..rings - 1 {
            faces.push(vec![ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)]);
            faces.push(vec![ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)]);
        }
    }
    clockwise(Mesh { points, faces })
}

/// A sphere of `slices` × `slices + 1` whose radius undulates with longitude at every latitude:
/// each pole is a fan of `slices` thin triangles whose outer ends rise and fall, so the solid
/// near the pole is a non-convex cone.
fn wiggly_sphere(slices: usize) -> Mesh {
    let stacks = slices + 1;
    let radius = |theta: f64, phi: f64| {
        1.0 + 0.15 * (5.0 * theta).sin() * (4.0 * phi).sin() + 0.05 * (13.0 * phi).sin()
    };
    let mut points = vec![DVec3::new(0.0, 0.0, 1.0), DVec3::new(0.0, 0.0, -1.0)];
    for i in 1..stacks {
        let theta = std::f64::consts::PI * i as f64 / stacks as f64;
        for j in 0..slices {
            let phi = std::f64::consts::TAU * j as f64 / slices as f64;
            points.push(
                radius(theta, phi)
                    * DVec3::new(
                        theta.sin() * phi.cos(),
                        theta.sin() * phi.sin(),
                        theta.cos(),
                    ),
            );
        }
    }
    let ring = |i: usize, j: usize| 2 + (i - 1) * slices + j % slices;
    let mut faces = Vec::new();
    for j in 0..slices {
        faces.push(vec![0, ring(1, j), ring(1, j + 1)]);
        faces.push(vec![1, ring(stacks - 1, j + 1), ring(stacks - 1, j)]);
        for i in 1..stacks - 1 {
            faces.push(vec![ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)]);
            faces.push(vec![ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)]);
        }
    }
    clockwise(Mesh { points, faces })
}

fn transformed(mesh: &Mesh, scale: f64, offset: DVec3) -> Mesh {
    Mesh {
        points: mesh.points.iter().map(|&p| p * scale + offset).collect(),
        faces: mesh.faces.clone(),
    }
}

fn max_planes(p: &Polyhedron) -> usize {
    p.cells.iter().map(|c| c.planes.len()).max().unwrap_or(0)
}

#[test]
fn a_box_in_openscad_order_is_itself() {
    let mesh = cuboid(DVec3::new(10.0, 7.0, 5.0));
    assert!(
        volume6(&mesh) < 0.0,
        "the documented order is clockwise seen from outside"
    );
    let polyhedron = check_membership(&mesh, 3000, 1);
    assert!(polyhedron.warnings.is_empty(), "{:?}", polyhedron.warnings);
    assert!(polyhedron.contains(DVec3::new(5.0, 3.0, 2.0)));
    assert!(!polyhedron.contains(DVec3::new(5.0, 3.0, 6.0)));
    assert_eq!(
        (polyhedron.min, polyhedron.max),
        (DVec3::ZERO, DVec3::new(10.0, 7.0, 5.0))
    );
}

#[test]
fn an_inside_out_box_warns_and_is_not_the_complement() {
    let mesh = reversed(&cuboid(DVec3::ONE));
    let polyhedron = polyhedron_cells(&mesh, &MeshLimits::default()).unwrap();
    assert!(polyhedron.contains(DVec3::splat(0.5)));
    assert!(!polyhedron.contains(DVec3::splat(2.0)));
    assert!(
        polyhedron.warnings.iter().any(|w| w.contains("inside out")),
        "{:?}",
        polyhedron.warnings
    );
}

#[test]
fn a_non_planar_face_is_triangulated_with_a_warning() {
    let mut mesh = cuboid(DVec3::ONE);
    mesh.points[6].z = 1.5;
    let polyhedron = check_membership(&mesh, 3000, 2);
    assert!(
        polyhedron.warnings.iter().any(|w| w.contains("not planar")),
        "{:?}",
        polyhedron.warnings
    );
}

#[test]
fn non_convex_and_toroidal_meshes_match_the_oracle() {
    let meshes = [torus(24, 12, 3.0, 1.0, 0.3), dented_sphere(12, 16, 0.3)];
    for (k, mesh) in meshes.iter().enumerate() {
        for (scale, offset) in [
            (1.0, DVec3::ZERO),
            (1e6, DVec3::ZERO),
            (1e-6, DVec3::ZERO),
            (1.0, DVec3::splat(1e6)),
        ] {
            let moved = transformed(mesh, scale, offset);
            let polyhedron = check_membership(&moved, 600, 10 + k as u64);
            assert!(polyhedron.warnings.is_empty(), "{:?}", polyhedron.warnings);
            assert!(
                max_planes(&polyhedron) <= 12,
                "a cell with {} planes",
                max_planes(&polyhedron)
            );
        }
    }
}

#[test]
fn a_large_mesh_gives_linearly_many_small_cells() {
    // 20,000 triangles.
    let mesh = torus(100, 100, 3.0, 1.0, 0.3);
    let triangles = mesh.faces.len();
    let polyhedron = check_membership(&mesh, 200, 3);
    assert!(
        polyhedron.cells.len() <= 12 * triangles,
        "{} cells for {triangles} triangles",
        polyhedron.cells.len()
    );
    assert!(max_planes(&polyhedron) <= 12);
}

#[test]
fn fans_around_a_pole_match_the_oracle_near_the_pole() {
    // Every triangle of a pole's fan meets the regions around the pole at the pole itself; the
    // partition leaves such triangles out of a region they do not reach into, which must not
    // change what the cells contain there.
    let mesh = wiggly_sphere(40);
    let polyhedron = check_membership(&mesh, 500, 21);
    assert!(polyhedron.warnings.is_empty(), "{:?}", polyhedron.warnings);
    assert!(
        polyhedron.cells.len() <= 5 * mesh.faces.len(),
        "{} cells for {} triangles",
        polyhedron.cells.len(),
        mesh.faces.len()
    );
    for (k, pole) in [DVec3::Z, DVec3::NEG_Z].into_iter().enumerate() {
        for reach in [0.2, 0.02] {
            let corner = DVec3::splat(reach);
            check_membership_in(
                &mesh,
                &polyhedron,
                pole - corner,
                pole + corner,
                1000,
                30 + k as u64,
            );
        }
    }
}

#[test]
fn bad_meshes_give_the_right_error() {
    let limits = MeshLimits::default();
    let cube = cuboid(DVec3::ONE);

    let mut open = cube.clone();
    open.faces.pop();
    let error = polyhedron_cells(&open, &limits).unwrap_err();
    assert!(matches!(error, MeshError::OpenEdge { .. }), "{error:?}");
    assert!(
        error.to_string().starts_with("open mesh: edge ("),
        "{error}"
    );

    let mut flipped = cube.clone();
    flipped.faces[0].reverse();
    let error = polyhedron_cells(&flipped, &limits).unwrap_err();
    assert!(
        matches!(
            error,
            MeshError::InconsistentOrientation { first: 0, .. }
                | MeshError::InconsistentOrientation { second: 0, .. }
        ),
        "{error:?}"
    );
    assert!(
        error.to_string().contains("oriented inconsistently"),
        "{error}"
    );

    let mut doubled = cube.clone();
    doubled
        .faces
        .push(cube.faces[0].iter().rev().copied().collect());
    doubled.faces.push(cube.faces[0].clone());
    let error = polyhedron_cells(&doubled, &limits).unwrap_err();
    assert!(
        matches!(error, MeshError::NonManifoldEdge { .. }),
        "{error:?}"
    );
    assert!(error.to_string().contains("non-manifold edge"), "{error}");

    let mut out_of_range = cube.clone();
    out_of_range.faces[2][1] = 99;
    assert_eq!(
        polyhedron_cells(&out_of_range, &limits).unwrap_err(),
        MeshError::IndexOutOfRange {
            face: 2,
            position: 1,
            index: 99,
            points: 8
        }
    );

    let mut degenerate = cube.clone();
    degenerate.faces.push(vec![1, 1, 2, 2]);
    assert_eq!(
        polyhedron_cells(&degenerate, &limits).unwrap_err(),
        MeshError::DegenerateFace { face: 6 }
    );

    let mut nan = cube.clone();
    nan.points[3].y = f64::NAN;
    assert_eq!(
        polyhedron_cells(&nan, &limits).unwrap_err(),
        MeshError::NonFinitePoint { index: 3 }
    );

    let small = MeshLimits {
        max_points: 4,
        ..MeshLimits::default()
    };
    assert!(matches!(
        polyhedron_cells(&cube, &small).unwrap_err(),
        MeshError::TooLarge { what: "points", .. }
    ));

    // No faces: an empty solid, not an error.
    assert!(
        polyhedron_cells(&Mesh::default(), &limits)
            .unwrap()
            .cells
            .is_empty()
    );
}

#[test]
fn two_boxes_sharing_only_an_edge_are_non_manifold_but_apart_are_fine() {
    let a = cuboid(DVec3::ONE);
    let mut both = a.clone();
    let shift = both.points.len();
    both.points
        .extend(a.points.iter().map(|&p| p + DVec3::new(3.0, 0.0, 0.0)));
    both.faces.extend(
        a.faces
            .iter()
            .map(|f| f.iter().map(|&i| i + shift).collect()),
    );
    let polyhedron = check_membership(&both, 2000, 4);
    assert!(polyhedron.contains(DVec3::new(3.5, 0.5, 0.5)));
}
