//! Exactness: quarter turns give exactly axis-aligned coefficients; far-off and tiny scenes
//! keep their relative precision through the DNF.

mod common;

use common::{cube, cylinder, sphere, src};
use qcsg_csg::{Dag, DnfOptions, build_dnf};
use qcsg_quadric::{DMat4, DVec3};

/// Rotation by +90° about X with exact 0/±1 entries.
fn quarter_x() -> DMat4 {
    DMat4::from_cols_array(&[
        1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
    ])
}

/// Rotation by +90° about Z with exact 0/±1 entries.
fn quarter_z() -> DMat4 {
    DMat4::from_cols_array(&[
        0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
    ])
}

#[test]
fn quarter_turns_give_axis_aligned_coefficients() {
    let mut dag = Dag::new();
    let c = cylinder(&mut dag, 1.5, 4.0, 0);
    let b = cube(&mut dag, DVec3::new(1.0, 2.0, 3.0), 1);
    let turned = DMat4::from_translation(DVec3::new(10.0, -3.0, 7.0)) * quarter_x() * quarter_z();
    let e1 = dag.edge(c, &turned).unwrap();
    let e2 = dag
        .edge(b, &(quarter_z() * quarter_z() * quarter_x()))
        .unwrap();
    let u = dag.union([e1, e2], src(2));
    dag.set_root(u.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    for q in &dnf.quadrics {
        let k = q.quadric.coefficients();
        // No cross terms, and every linear term belongs to an axis that has no square term
        // (about its local origin, an axis-aligned slab or cylinder has no linear part at all).
        assert_eq!(&k[3..6], &[0.0, 0.0, 0.0], "cross terms in {k:?}");
        assert_eq!(&k[6..9], &[0.0, 0.0, 0.0], "linear terms in {k:?}");
        let nonzero: Vec<f64> = k[..3].iter().copied().filter(|v| *v != 0.0).collect();
        assert!(
            nonzero.windows(2).all(|w| w[0] == w[1]),
            "unequal squares in {k:?}"
        );
    }
    // The cylinder's axis Z turned about Z then X lies along −Y: its square terms are x and z.
    let side = dnf
        .quadrics
        .iter()
        .find(|q| q.quadric.kind().name().contains("cylinder"))
        .unwrap();
    let k = side.quadric.coefficients();
    assert!(k[0] > 0.0 && k[1] == 0.0 && k[2] > 0.0, "{k:?}");
    assert_eq!(k[0], k[2]);
    assert_eq!(side.quadric.origin(), DVec3::new(10.0, -3.0, 7.0));
}

#[test]
fn far_off_sphere_keeps_its_radius() {
    let offset = DVec3::new(1e6, -2e6, 3e6);
    let mut dag = Dag::new();
    let s = sphere(&mut dag, 1.0, 0);
    let b = cube(&mut dag, DVec3::splat(1.0), 1);
    let s_edge = dag.translated(s.into(), offset).unwrap();
    let b_edge = dag.translated(b.into(), offset).unwrap();
    let d = dag.difference([s_edge, b_edge], src(2));
    dag.set_root(d.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    let ball = dnf
        .quadrics
        .iter()
        .find(|q| q.quadric.kind().name() == "sphere")
        .unwrap();
    assert_eq!(ball.quadric.origin(), offset);
    let k = ball.quadric.coefficients();
    assert_eq!(k[0], -k[9], "radius 1 exactly: a = −j, got {k:?}");
    for p in [0.999_999, 1.000_001] {
        let x = offset + DVec3::new(-p, 0.0, 0.0);
        assert_eq!(dnf.contains(x), p < 1.0, "at distance {p}");
        assert_eq!(dag.contains(x), p < 1.0);
    }
    // The far corner of the cube is cut away, 1e-6 inside it.
    let corner = offset + DVec3::splat(0.5);
    assert!(!dnf.contains(corner));
    assert!(dnf.bounds.max.x - offset.x < 1.0 + 1e-6 && offset.x - dnf.bounds.min.x < 1.0 + 1e-6);
}

#[test]
fn tiny_scene_keeps_relative_precision() {
    let mut dag = Dag::new();
    let s = sphere(&mut dag, 1e-3, 0);
    let turned = DMat4::from_translation(DVec3::splat(2e-3)) * DMat4::from_rotation_y(0.7);
    let e = dag.edge(s, &turned).unwrap();
    let c = cube(&mut dag, DVec3::splat(2e-3), 1);
    let c = dag.translated(c.into(), DVec3::splat(1e-3)).unwrap();
    let u = dag.intersection([e, c], src(2));
    dag.set_root(u.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    let ball = dnf
        .quadrics
        .iter()
        .find(|q| q.quadric.kind().name() == "sphere")
        .unwrap();
    let k = ball.quadric.coefficients();
    let radius = (-k[9] / k[0]).sqrt();
    assert!((radius / 1e-3 - 1.0).abs() < 1e-14, "radius {radius}");
    for p in [0.999_999e-3, 1.000_001e-3] {
        let x = DVec3::splat(2e-3) + DVec3::new(0.0, -p, 0.0);
        assert_eq!(dnf.contains(x), p < 1e-3, "at distance {p}");
    }
}
