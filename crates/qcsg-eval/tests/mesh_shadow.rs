//! `projection(cut = false)` of meshes (polyhedron, import), checked against an exact reference:
//! a non-convex prism is a union of boxes, and the shadow of a box under an affine map is the
//! convex hull of its corners' projections, so the shadow is the union of those hulls.

mod common;

use common::{codes, eval};
use glam::{DMat4, DVec2, DVec3};
use qcsg_csg::{DnfOptions, build_dnf};
use qcsg_eval::transforms::rotate_xyz;

/// The notched L of the polyhedron scene, as a prism 4 high.
const L_PRISM: &str = "
    l = [[0, 0], [8, 0], [8, 3], [5, 3], [5, 2], [3, 2], [3, 8], [0, 8]];
    n = len(l);
    module prism() polyhedron(
        points = concat([for (q = l) [q[0], q[1], 0]], [for (q = l) [q[0], q[1], 4]]),
        faces = [
            [for (i = [0 : n - 1]) i],
            [for (i = [n - 1 : -1 : 0]) i + n],
            for (i = [0 : n - 1]) [i, i + n, (i + 1) % n + n, (i + 1) % n]
        ]);
";

/// The same prism as boxes (min, max).
const L_BOXES: [([f64; 3], [f64; 3]); 3] = [
    ([0.0, 0.0, 0.0], [8.0, 2.0, 4.0]),
    ([0.0, 0.0, 0.0], [3.0, 8.0, 4.0]),
    ([5.0, 2.0, 0.0], [8.0, 3.0, 4.0]),
];

/// The convex hull of `points`, counter-clockwise (Andrew's monotone chain).
fn hull(mut points: Vec<DVec2>) -> Vec<DVec2> {
    points.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    let cross = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let mut out: Vec<DVec2> = Vec::new();
    for pass in 0..2 {
        let start = out.len();
        for &p in &points {
            while out.len() >= start + 2 && cross(out[out.len() - 2], out[out.len() - 1], p) <= 0.0
            {
                out.pop();
            }
            out.push(p);
        }
        out.pop();
        if pass == 0 {
            points.reverse();
        }
    }
    out
}

/// The signed distance from `p` to convex `polygon` (negative inside), as the largest distance
/// beyond an edge's line.
fn signed_distance(polygon: &[DVec2], p: DVec2) -> f64 {
    (0..polygon.len())
        .map(|k| {
            let (a, b) = (polygon[k], polygon[(k + 1) % polygon.len()]);
            let d = b - a;
            -(d.perp_dot(p - a)) / d.length()
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The hulls of the boxes' corners seen through `m`.
fn reference(m: &DMat4) -> Vec<Vec<DVec2>> {
    L_BOXES
        .iter()
        .map(|(lo, hi)| {
            let corners = (0..8)
                .map(|i| {
                    let c = DVec3::new(
                        if i & 1 == 0 { lo[0] } else { hi[0] },
                        if i & 2 == 0 { lo[1] } else { hi[1] },
                        if i & 4 == 0 { lo[2] } else { hi[2] },
                    );
                    m.transform_point3(c).truncate()
                })
                .collect();
            hull(corners)
        })
        .collect()
}

/// Evaluates `linear_extrude(1) projection() multmatrix(m) prism();` and compares the DAG and
/// the DNF with the reference at points of a grid over the shadow's box, away from its edges by
/// `margin`.
fn check_prism(m: DMat4, margin: f64) {
    let rows: Vec<String> = (0..4)
        .map(|r| {
            let v = m.row(r);
            format!("[{:e}, {:e}, {:e}, {:e}]", v.x, v.y, v.z, v.w)
        })
        .collect();
    let text = format!(
        "{L_PRISM}\nlinear_extrude(1) projection() multmatrix([{}]) prism();",
        rows.join(", ")
    );
    let e = eval(&text);
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    let dnf = build_dnf(&e.dag, &DnfOptions::default()).expect("a bounded solid");
    let hulls = reference(&m);
    let (lo, hi) = hulls
        .iter()
        .flatten()
        .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    let pad = (hi - lo) * 0.05;
    let (lo, hi) = (lo - pad, hi + pad);
    let (mut inside, mut outside) = (0, 0);
    let steps = 40;
    for i in 0..=steps {
        for j in 0..=steps {
            let t = DVec2::new(i as f64, j as f64) / steps as f64;
            let p = lo + (hi - lo) * t;
            let d = hulls
                .iter()
                .map(|h| signed_distance(h, p))
                .fold(f64::INFINITY, f64::min);
            if d.abs() < margin {
                continue;
            }
            let want = d < 0.0;
            let q = p.extend(0.5);
            assert_eq!(e.dag.contains(q), want, "DAG at {p} (distance {d})");
            assert_eq!(dnf.contains(q), want, "DNF at {p} (distance {d})");
            if want { inside += 1 } else { outside += 1 }
        }
    }
    assert!(
        inside > 100 && outside > 100,
        "{inside} inside, {outside} outside"
    );
}

#[test]
fn the_shadow_of_a_turned_non_convex_polyhedron() {
    check_prism(rotate_xyz(30.0, 40.0, 10.0), 1e-9);
    check_prism(rotate_xyz(90.0, 0.0, 0.0), 1e-9);
    check_prism(rotate_xyz(-70.0, 15.0, 200.0), 1e-9);
    // Seen from above (the top and bottom coincide) and upside down.
    check_prism(DMat4::IDENTITY, 1e-9);
    check_prism(rotate_xyz(180.0, 0.0, 0.0), 1e-9);
}

#[test]
fn a_mirrored_and_sheared_polyhedron() {
    let mut shear = DMat4::from_scale(DVec3::new(-1.0, 2.0, 0.5));
    shear.z_axis.x = 0.7;
    shear.y_axis.z = -0.4;
    check_prism(rotate_xyz(20.0, 0.0, 35.0) * shear, 1e-9);
}

#[test]
fn far_and_tiny_polyhedra() {
    let turn = rotate_xyz(25.0, 50.0, 5.0);
    let far = DMat4::from_translation(DVec3::new(1e6, -2e6, 3e6)) * turn;
    check_prism(far, 1e-7);
    check_prism(DMat4::from_scale(DVec3::splat(1e-6)) * turn, 1e-15);
    check_prism(DMat4::from_scale(DVec3::splat(1e6)) * turn, 1e-3);
}

#[test]
fn a_mesh_in_a_union_with_a_ball() {
    let e = eval(&format!(
        "{L_PRISM}\nlinear_extrude(1) projection() {{
             rotate([90, 0, 0]) prism();
             translate([20, 0, 5]) sphere(2, $fn = 64);
         }}"
    ));
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    // Turned about x (y to z, z to −y) the prism's shadow is [0, 8] × [−4, 0]; the ball's a
    // disc of radius 2.
    for (x, y, inside) in [
        (7.5, -3.5, true),
        (0.5, -0.5, true),
        (8.5, -2.0, false),
        (4.0, 0.5, false),
        (21.9, 0.0, true),
        (22.1, 0.0, false),
    ] {
        assert_eq!(e.dag.contains(DVec3::new(x, y, 0.5)), inside, "at {x}, {y}");
    }
}

#[test]
fn a_flat_mesh_casts_no_shadow() {
    // Two faces back to back in the plane x = 0: every face seen edge-on.
    let e = eval(
        "linear_extrude(1) projection() polyhedron(
             points = [[0, 0, 0], [0, 4, 0], [0, 0, 4]], faces = [[0, 1, 2], [0, 2, 1]]);",
    );
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    assert!(!e.dag.contains(DVec3::new(0.0, 1.0, 0.5)));
    assert!(!e.dag.contains(DVec3::new(0.1, 1.0, 0.5)));
}

#[test]
fn a_mesh_cut_by_a_z_dependent_part_is_refused_at_the_call() {
    let text = format!(
        "{L_PRISM}\nlinear_extrude(1) projection() intersection() {{ prism(); sphere(3); }}"
    );
    let e = eval(&text);
    assert!(codes(&e).contains(&"E0301"), "{:?}", e.diagnostics);
    let d = e.diagnostics.iter().find(|d| d.is_error()).unwrap();
    assert!(text[d.span.start as usize..d.span.end as usize].starts_with("projection()"));
    assert!(!d.labels.is_empty());
}

#[test]
fn an_imported_stl_projects_as_its_polyhedron() {
    // The star prism OpenSCAD exported, turned: the shadow from the file and from the same
    // mesh given to polyhedron agree.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/openscad/lib");
    let path = dir.join("star_prism.stl");
    let e = eval(&format!(
        "linear_extrude(1) projection() rotate([35, 20, 0]) import(\"{}\");",
        path.display()
    ));
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    let dnf = build_dnf(&e.dag, &DnfOptions::default()).expect("a bounded solid");
    let mut inside = 0;
    for i in -30..=30 {
        for j in -30..=30 {
            let q = DVec3::new(i as f64 * 0.4, j as f64 * 0.4, 0.5);
            let a = e.dag.contains(q);
            assert_eq!(a, dnf.contains(q), "at {q}");
            inside += a as usize;
        }
    }
    assert!(inside > 50, "{inside}");
}

#[test]
fn a_surface_casts_its_grid() {
    // A 3 × 4 height map: OpenSCAD's mesh covers x in [0, 3], y in [0, 2] (columns, rows), with
    // hills and a pit; seen from above and turned on its side.
    let dir = std::env::temp_dir().join(format!("qcsg-mesh-shadow-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("map.dat"), "1 4 2 0\n3 -2 5 1\n0 2 2 7\n").unwrap();
    let map = dir.join("map.dat");
    let e = eval(&format!(
        "linear_extrude(1) projection() surface(\"{}\");
         translate([10, 0, 0]) linear_extrude(1) projection() rotate([90, 0, 0]) surface(\"{}\");",
        map.display(),
        map.display()
    ));
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    let at = |x: f64, y: f64| e.dag.contains(DVec3::new(x, y, 0.5));
    assert!(at(0.1, 0.1) && at(2.9, 1.9) && at(1.5, 1.0));
    assert!(!at(-0.1, 1.0) && !at(3.1, 1.0) && !at(1.0, 2.1) && !at(1.0, -0.1));
    // On its side the shadow spans x in [0, 3] and the heights, from the base at z = −3 (the
    // lowest height less one) up to 7 at x = 3, y = 2 (6.75 at x = 2.95), seen as y from −7 to 3.
    assert!(at(10.1, 2.9) && at(12.95, -6.5) && at(11.5, 0.0));
    assert!(!at(10.1, -6.9) && !at(13.1, 0.0) && !at(11.0, 3.1));
}
