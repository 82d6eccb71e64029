//! DNF construction on hand-built scenes: meaning, bounds, diagnostics.

mod common;

use common::{cube, cylinder, sphere, src};
use qcsg_csg::{Aabb, Dag, DnfOptions, build_dnf, codes};
use qcsg_quadric::{DMat4, DVec3, Quadric};

fn grid_points(bounds: &Aabb, n: usize) -> Vec<DVec3> {
    let mut points = Vec::new();
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let t = DVec3::new(i as f64, j as f64, k as f64) / (n as f64 - 1.0);
                points.push(bounds.min + t * (bounds.max - bounds.min));
            }
        }
    }
    points
}

#[test]
fn cube_minus_sphere_matches_the_dag() {
    let mut dag = Dag::new();
    let c = cube(&mut dag, DVec3::splat(2.0), 0);
    let s = sphere(&mut dag, 1.2, 10);
    let s = dag.translated(s.into(), DVec3::splat(2.0)).unwrap();
    let d = dag.difference([c.into(), s], src(20));
    dag.set_root(d.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    println!("{}", dnf.stats);
    assert_eq!(dnf.terms.len(), 1, "{:?}", dnf.terms);
    assert_eq!(dnf.terms[0].literals.len(), 4);
    let probe = Aabb::new(DVec3::splat(-0.5), DVec3::splat(2.5));
    for p in grid_points(&probe, 17) {
        assert_eq!(dag.contains(p), dnf.contains(p), "{p}");
    }
    assert!(
        dnf.bounds
            .contains_box(&Aabb::new(DVec3::ZERO, DVec3::splat(2.0)))
    );
    assert!(dnf.bounds.max.max_element() < 2.0 + 1e-6);
}

#[test]
fn rotated_cube_stays_bounded() {
    let mut dag = Dag::new();
    let c = cube(&mut dag, DVec3::ONE, 0);
    let e = dag.edge(c, &DMat4::from_rotation_z(0.3)).unwrap();
    dag.set_root(e);
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    assert_eq!(dnf.terms.len(), 1);
    assert!(dnf.bounds.is_bounded());
}

#[test]
fn unbounded_result_names_the_part() {
    let mut dag = Dag::new();
    let s = sphere(&mut dag, 1.0, 0);
    let half = dag.leaf(Quadric::half_space(DVec3::ZERO, DVec3::X).unwrap(), src(42));
    let u = dag.union([s.into(), half.into()], src(50));
    dag.set_root(u.into());
    let errors = build_dnf(&dag, &DnfOptions::default()).unwrap_err();
    assert_eq!(errors.len(), 1);
    assert_eq!(errors[0].code, codes::UNBOUNDED);
    assert_eq!(errors[0].span.start, 42);
    // The same half-space cut by the sphere is fine.
    let i = dag.intersection([s.into(), half.into()], src(60));
    dag.set_root(i.into());
    assert!(build_dnf(&dag, &DnfOptions::default()).is_ok());
}

#[test]
fn term_limit_is_a_diagnostic_not_a_hang() {
    // A block minus 400 cubes scattered inside it: every cube is three terms of its complement.
    let mut dag = Dag::new();
    let block = cube(&mut dag, DVec3::splat(100.0), 0);
    let mut children = vec![block.into()];
    for i in 0..400 {
        let c = cube(&mut dag, DVec3::splat(1.0), 1000 + i);
        let offset = DVec3::new(
            (i % 20) as f64 * 4.0 + 2.0,
            (i / 20) as f64 * 4.0 + 2.0,
            50.0 + (i % 7) as f64,
        );
        children.push(dag.translated(c.into(), offset).unwrap());
    }
    let d = dag.difference(children, src(7));
    dag.set_root(d.into());
    let start = std::time::Instant::now();
    let errors = build_dnf(
        &dag,
        &DnfOptions {
            term_limit: 1_000,
            ..DnfOptions::default()
        },
    )
    .unwrap_err();
    assert!(start.elapsed().as_secs_f64() < 5.0);
    assert_eq!(errors[0].code, codes::TERM_LIMIT);
}

#[test]
fn cylinder_row_and_colours() {
    let mut dag = Dag::new();
    let c = cylinder(&mut dag, 1.0, 3.0, 0);
    let red = dag.color(c.into(), [1.0, 0.0, 0.0, 1.0], src(5)).unwrap();
    let moved = dag
        .translated(red.into(), DVec3::new(5.0, 0.0, 0.0))
        .unwrap();
    let u = dag.union([c.into(), moved], src(9));
    dag.set_root(u.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    assert_eq!(dnf.terms.len(), 2);
    assert!(
        dnf.quadrics
            .iter()
            .any(|q| q.color == Some([1.0, 0.0, 0.0, 1.0]))
    );
    assert!(dnf.quadrics.iter().any(|q| q.color.is_none()));
    assert!(dnf.contains(DVec3::new(5.0, 0.0, 1.0)) && !dnf.contains(DVec3::new(2.5, 0.0, 1.0)));
}

#[test]
fn no_root_is_an_error() {
    let dag = Dag::new();
    assert_eq!(
        build_dnf(&dag, &DnfOptions::default()).unwrap_err()[0].code,
        codes::NO_ROOT
    );
}

#[test]
fn deep_dags_build_without_overflowing_the_stack() {
    let mut dag = Dag::new();
    let mut node = sphere(&mut dag, 1.0, 0);
    for i in 0..50_000 {
        let step = dag
            .translated(node.into(), DVec3::new(1e-6, 0.0, 0.0))
            .unwrap();
        node = if i % 2 == 0 {
            dag.union([step], src(i))
        } else {
            dag.intersection([step], src(i))
        };
    }
    dag.set_root(node.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    assert_eq!(dnf.terms.len(), 1);
    assert!(dnf.contains(DVec3::new(0.05, 0.0, 0.0)));
}

#[test]
fn tilted_box_of_half_spaces_is_bounded() {
    let mut dag = Dag::new();
    let rotation = DMat4::from_rotation_z(0.4) * DMat4::from_rotation_x(0.3);
    let mut faces = Vec::new();
    for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
        for sign in [1.0, -1.0] {
            let normal = rotation.transform_vector3(axis * sign);
            let q = Quadric::half_space(normal, normal).unwrap();
            faces.push(dag.leaf(q, src(faces.len())).into());
        }
    }
    let all = dag.intersection(faces.clone(), src(10));
    dag.set_root(all.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    assert!(dnf.bounds.is_bounded());
    assert!((dnf.bounds.max - dnf.bounds.min).max_element() < 4.0);
    // Five faces leave it open: the error names a face.
    let open = dag.intersection(faces[..5].to_vec(), src(11));
    dag.set_root(open.into());
    let errors = build_dnf(&dag, &DnfOptions::default()).unwrap_err();
    assert_eq!(errors[0].code, codes::UNBOUNDED);
    assert!(errors[0].span.start < 5);
}

#[test]
fn projective_transforms_keep_membership() {
    let mut dag = Dag::new();
    let c = cube(&mut dag, DVec3::splat(2.0), 0);
    let s = sphere(&mut dag, 1.0, 1);
    let s = dag.translated(s.into(), DVec3::splat(2.0)).unwrap();
    let d = dag.difference([c.into(), s], src(2));
    // A mild perspective: w = 1 + 0.05 x + 0.02 z stays positive over the part.
    let projective = DMat4::from_cols_array(&[
        1.0, 0.1, 0.0, 0.05, 0.0, 1.0, 0.0, 0.0, 0.2, 0.0, 1.0, 0.02, 0.5, 0.0, 0.0, 1.0,
    ]);
    let e = dag.edge(d, &projective).unwrap();
    dag.set_root(e);
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    let probe = Aabb::new(DVec3::splat(-1.0), DVec3::splat(3.5));
    let mut inside = 0;
    for p in grid_points(&probe, 19) {
        let near = dnf
            .quadrics
            .iter()
            .any(|q| q.quadric.conservative_distance(p).abs() < 1e-7);
        if near {
            continue;
        }
        assert_eq!(dag.contains(p), dnf.contains(p), "{p}");
        inside += usize::from(dnf.contains(p));
    }
    assert!(inside > 100);
    assert!(dnf.bounds.is_bounded());
}

#[test]
fn singular_transforms_flatten_parts_away_with_a_warning() {
    let mut dag = Dag::new();
    let s = sphere(&mut dag, 1.0, 0);
    let flat = dag
        .edge(s, &DMat4::from_scale(DVec3::new(1.0, 1.0, 0.0)))
        .unwrap();
    let moved = dag.translated(s.into(), DVec3::new(3.0, 0.0, 0.0)).unwrap();
    let u = dag.union([moved, flat], src(1));
    dag.set_root(u.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    assert_eq!(dnf.terms.len(), 1);
    assert_eq!(dnf.warnings.len(), 1);
    assert_eq!(dnf.warnings[0].code, codes::SINGULAR_TRANSFORM);
    // Subtracting a flattened part subtracts nothing.
    let d = dag.difference([moved, flat], src(2));
    dag.set_root(d.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    assert!(dnf.contains(DVec3::new(3.0, 0.0, 0.0)));
}

#[test]
fn complement_alone_is_all_of_space_and_an_error() {
    let mut dag = Dag::new();
    let s = sphere(&mut dag, 1.0, 0);
    let c = dag.complement(s.into(), src(8));
    dag.set_root(c.into());
    let errors = build_dnf(&dag, &DnfOptions::default()).unwrap_err();
    assert_eq!(errors[0].code, codes::UNBOUNDED);
    // Within a region it is fine: the region's part of it.
    let region = Aabb::new(DVec3::splat(-2.0), DVec3::splat(2.0));
    let dnf = build_dnf(
        &dag,
        &DnfOptions {
            region: Some(region),
            ..DnfOptions::default()
        },
    )
    .unwrap();
    assert!(dnf.contains(DVec3::splat(1.5)) && !dnf.contains(DVec3::ZERO));
    // A cube minus the complement of a sphere is their intersection.
    let cube_node = cube(&mut dag, DVec3::splat(2.0), 9);
    let d = dag.difference([cube_node.into(), c.into()], src(10));
    dag.set_root(d.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    assert!(dnf.contains(DVec3::splat(0.5)) && !dnf.contains(DVec3::splat(1.5)));
}
