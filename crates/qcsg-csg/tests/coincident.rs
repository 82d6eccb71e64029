//! One notion of "the same surface" ([`qcsg_csg::coincident`]): copies of a surface placed by
//! different transforms (turned, moved by 10⁵, scaled by 10⁻³) are one surface; thin walls
//! (10⁻⁹, 10⁻⁶), a ball resting on a plane and touching balls are not. Terms emptied by a
//! coincident pair are pruned; terms that only share a face are kept. Finding the surfaces stays
//! near-linear in the number of quadrics.

mod common;

use common::{cube, cylinder, sphere, src};
use qcsg_csg::coincident::{MAX_CANDIDATES_PER_CELL, has_coincident_pair};
use qcsg_csg::dnf::Pruning;
use qcsg_csg::{Dag, Dnf, DnfOptions, Rounding, Sheet, Surfaces, build_dnf, find_surfaces};
use qcsg_quadric::{DMat4, DVec3, Quadric};
use qcsg_testkit::Rng;

/// `q` placed by `m`, with the rounding the DNF would record for it.
fn placed(q: &Quadric, m: &DMat4) -> (Quadric, Rounding) {
    (
        q.transformed(m).expect("invertible"),
        Rounding::of_placement(m, q.origin()),
    )
}

fn surfaces_of(quadrics: &[(Quadric, Rounding)]) -> Surfaces {
    find_surfaces(quadrics.iter().map(|(q, r)| (q, *r)))
}

fn sheets(surfaces: &Surfaces, quadric: u32) -> Vec<Sheet> {
    surfaces.of(quadric).expect("described").to_vec()
}

/// The placements every "one surface" case is checked under.
fn placements() -> Vec<(&'static str, DMat4)> {
    let turn = DMat4::from_axis_angle(DVec3::new(1.0, 1.0, 0.0).normalize(), 37f64.to_radians());
    let far = DMat4::from_translation(DVec3::new(1e5, -1e5, 1e5));
    let small = DMat4::from_scale(DVec3::splat(1e-3));
    vec![
        ("as written", DMat4::IDENTITY),
        ("turned about z", DMat4::from_rotation_z(37f64.to_radians())),
        ("turned about a skew axis", turn),
        ("moved by 1e5", far),
        ("turned and moved by 1e5", far * turn),
        ("turned and scaled by 1e-3", small * turn),
        ("turned, scaled and moved", far * small * turn),
    ]
}

#[test]
fn a_cutters_flush_face_is_the_parts_face_under_any_placement() {
    // cube([20, 10, 10])'s z-slab, a notch's cutter translate([5, 0, 5]) cube([10, 10, 5]), and
    // the half-space z ≤ 10.
    let part = Quadric::slab(DVec3::new(10.0, 5.0, 5.0), DVec3::Z, 5.0).unwrap();
    let cutter = Quadric::slab(DVec3::new(10.0, 5.0, 7.5), DVec3::Z, 2.5).unwrap();
    let lid = Quadric::half_space(DVec3::new(3.0, 1.0, 10.0), DVec3::Z).unwrap();
    for (name, m) in placements() {
        let quadrics = [
            placed(&part, &m),
            placed(&cutter.negated(), &m),
            placed(&lid, &m),
        ];
        let surfaces = surfaces_of(&quadrics);
        let (part, cutter, lid) = (
            sheets(&surfaces, 0),
            sheets(&surfaces, 1),
            sheets(&surfaces, 2),
        );
        assert_eq!((part.len(), cutter.len(), lid.len()), (2, 2, 1), "{name}");
        // Each plane is found once: z = 0, z = 10 (shared by all three), z = 5.
        assert_eq!(surfaces.len(), 3, "{name}: {surfaces:?}");
        let top = |s: &[Sheet]| {
            *s.iter()
                .find(|x| x.surface == lid[0].surface)
                .unwrap_or_else(|| panic!("{name}: no sheet on the lid's plane: {s:?}"))
        };
        let (part_top, cutter_top) = (top(&part), top(&cutter));
        // The part and the half-space face out of z = 10 alike; the cutter's complement faces in.
        assert_eq!(part_top.orientation, lid[0].orientation, "{name}");
        assert_eq!(cutter_top.orientation, -part_top.orientation, "{name}");
        assert!(part_top.one_sided && !cutter_top.one_sided && lid[0].one_sided);
        assert_eq!(surfaces.surface(lid[0].surface).unwrap().sheets, 3);
        assert!(surfaces.surface(lid[0].surface).unwrap().planar);
    }
}

#[test]
fn a_ball_and_its_turned_copies_are_one_surface_with_their_orientation() {
    let ball = Quadric::sphere(DVec3::ZERO, 5.0).unwrap();
    let turns = [
        DMat4::from_rotation_z(30f64.to_radians()),
        DMat4::from_rotation_z(40f64.to_radians())
            * DMat4::from_rotation_y(30f64.to_radians())
            * DMat4::from_rotation_x(20f64.to_radians()),
    ];
    for (name, m) in placements() {
        for turn in turns {
            let quadrics = [placed(&ball, &m), placed(&ball.negated(), &(m * turn))];
            let surfaces = surfaces_of(&quadrics);
            let (a, b) = (sheets(&surfaces, 0), sheets(&surfaces, 1));
            assert_eq!(surfaces.len(), 1, "{name}");
            assert_eq!(
                (a[0].surface, a[0].orientation, b[0].orientation),
                (0, 1, -1),
                "{name}"
            );
            assert!(surfaces.meet_only_on_surface(0, 1), "{name}");
            assert!(has_coincident_pair(&surfaces, &[0, 1]), "{name}");
        }
    }
}

#[test]
fn coaxial_cylinders_of_one_radius_are_one_surface_wherever_their_origins_lie() {
    // cylinder(h = 10, r = 5) and translate([0, 0, 5]) cylinder(h = 5, r = 5), as evaluated:
    // the lateral surfaces keep their primitives' centres as origins, 2.5 apart along the axis.
    let low = Quadric::cylinder(DVec3::new(0.0, 0.0, 5.0), DVec3::Z, 5.0).unwrap();
    let high = Quadric::cylinder(DVec3::new(0.0, 0.0, 7.5), DVec3::Z, 5.0).unwrap();
    let narrower = Quadric::cylinder(DVec3::new(0.0, 0.0, 7.5), DVec3::Z, 3.0).unwrap();
    for (name, m) in placements() {
        let quadrics = [
            placed(&low, &m),
            placed(&high.negated(), &m),
            placed(&narrower, &m),
        ];
        let surfaces = surfaces_of(&quadrics);
        let (a, b, c) = (
            sheets(&surfaces, 0),
            sheets(&surfaces, 1),
            sheets(&surfaces, 2),
        );
        assert_eq!(a[0].surface, b[0].surface, "{name}");
        assert_eq!(b[0].orientation, -1, "{name}");
        assert_ne!(a[0].surface, c[0].surface, "{name}");
        assert!(!surfaces.surface(a[0].surface).unwrap().planar);
    }
}

#[test]
fn thin_walls_are_not_merged() {
    for gap in [1e-9, 1e-6] {
        // cube([1, 1, 1]) and translate([1 + gap, 0, 0]) cube([1, 1, 1]): faces gap apart.
        let left = Quadric::slab(DVec3::splat(0.5), DVec3::X, 0.5).unwrap();
        let right = Quadric::slab(DVec3::new(1.5 + gap, 0.5, 0.5), DVec3::X, 0.5).unwrap();
        // Nested balls gap apart, and the half-spaces x ≤ 1 and x ≥ 1 + gap.
        let inner = Quadric::sphere(DVec3::ZERO, 5.0).unwrap();
        let outer = Quadric::sphere(DVec3::ZERO, 5.0 + gap).unwrap();
        let below = Quadric::half_space(DVec3::X, DVec3::X).unwrap();
        let above = Quadric::half_space(DVec3::new(1.0 + gap, 0.0, 0.0), -DVec3::X).unwrap();
        let mut placements = placements();
        if gap < 1e-6 {
            // Scaled by 1e-3 and moved by 1e5, a wall of 1e-9 is 1e-12 thick: a tenth of a unit
            // in the last place of its coordinates, within their rounding.
            placements.retain(|(name, _)| *name != "turned, scaled and moved");
        }
        for (name, m) in placements {
            let quadrics = [
                placed(&left, &m),
                placed(&right, &m),
                placed(&inner, &m),
                placed(&outer.negated(), &m),
                placed(&below, &m),
                placed(&above, &m),
            ];
            let surfaces = surfaces_of(&quadrics);
            // Planes x = 0, 1, 1 + gap, 2 + gap and two spheres: nothing merged but the
            // half-spaces with the slabs' faces.
            assert_eq!(surfaces.len(), 6, "{gap} {name}: {surfaces:?}");
            let shared = |q: u32| {
                sheets(&surfaces, q)
                    .iter()
                    .map(|s| s.surface)
                    .collect::<Vec<_>>()
            };
            assert!(shared(0).contains(&shared(4)[0]), "{gap} {name}");
            assert!(shared(1).contains(&shared(5)[0]), "{gap} {name}");
            assert!(!surfaces.meet_only_on_surface(4, 5), "{gap} {name}");
            assert!(!surfaces.meet_only_on_surface(2, 3), "{gap} {name}");
        }
    }
}

#[test]
fn tangent_surfaces_are_not_merged() {
    for (name, m) in placements() {
        let quadrics = [
            // A ball resting on the plane z = 0, and a half-space across it.
            placed(
                &Quadric::sphere(DVec3::new(0.0, 0.0, 1.0), 1.0).unwrap(),
                &m,
            ),
            placed(&Quadric::half_space(DVec3::ZERO, DVec3::Z).unwrap(), &m),
            // Two touching balls.
            placed(
                &Quadric::sphere(DVec3::new(2.0, 0.0, 1.0), 1.0).unwrap(),
                &m,
            ),
            // A ball touching the first from inside.
            placed(
                &Quadric::sphere(DVec3::new(0.0, 0.0, 0.5), 0.5).unwrap(),
                &m,
            ),
        ];
        let surfaces = surfaces_of(&quadrics);
        assert_eq!(surfaces.len(), 4, "{name}");
        assert!(!has_coincident_pair(&surfaces, &[0, 1, 2, 3]), "{name}");
    }
}

fn build(dag: &Dag, pruning: Pruning) -> Dnf {
    build_dnf(
        dag,
        &DnfOptions {
            pruning,
            ..DnfOptions::default()
        },
    )
    .unwrap()
}

fn pass_removed(dnf: &Dnf) -> usize {
    dnf.stats
        .passes
        .iter()
        .find(|p| p.pass == "coincident_pairs")
        .map_or(0, |p| p.terms_before - p.terms_after)
}

#[test]
fn a_ball_minus_its_turned_copy_is_pruned_to_nothing() {
    let mut dag = Dag::new();
    let ball = sphere(&mut dag, 5.0, 0);
    let turned = dag
        .edge(ball, &DMat4::from_rotation_z(30f64.to_radians()))
        .unwrap();
    let solid = dag.difference([ball.into(), turned], src(1));
    dag.set_root(solid.into());
    let dnf = build(&dag, Pruning::all());
    assert!(dnf.terms.is_empty(), "{}", dnf.stats);
    assert_eq!(pass_removed(&dnf), 1);
    assert!(dnf.surfaces.is_empty() && dnf.quadrics.is_empty());
    // Without the rule the term stays, and both quadrics are one surface.
    let dnf = build(&dag, Pruning::without("final_coincident_pairs").unwrap());
    assert_eq!(dnf.terms.len(), 1);
    assert_eq!(dnf.surfaces.len(), 1);
    assert!(has_coincident_pair(&dnf.surfaces, &dnf.terms[0].literals));
}

#[test]
fn a_flush_tube_loses_the_term_of_its_slab_and_the_slabs_complement() {
    // difference() { cylinder(h = 10, r = 5); cylinder(h = 10, r = 3); }, the bore's caps
    // placed about another origin than the tube's (as a translated primitive would be).
    let mut dag = Dag::new();
    let tube = cylinder(&mut dag, 5.0, 10.0, 0);
    let side = Quadric::cylinder(DVec3::ZERO, DVec3::Z, 3.0).unwrap();
    let caps = Quadric::slab(DVec3::new(1.0, 2.0, 5.0), DVec3::Z, 5.0).unwrap();
    let side = dag.leaf(side, src(1));
    let caps = dag.leaf(caps, src(1));
    let bore = dag.intersection([side.into(), caps.into()], src(1));
    let solid = dag.difference([tube.into(), bore.into()], src(2));
    dag.set_root(solid.into());
    let unpruned = build(&dag, Pruning::without("final_coincident_pairs").unwrap());
    let dnf = build(&dag, Pruning::all());
    assert_eq!(pass_removed(&dnf), 1, "{}", dnf.stats);
    assert_eq!(dnf.terms.len() + 1, unpruned.terms.len());
    // The term left is the tube's wall: outside the bore's side.
    assert!(dnf.contains(DVec3::new(4.0, 0.0, 5.0)) && !dnf.contains(DVec3::new(2.0, 0.0, 5.0)));
}

#[test]
fn opposite_half_spaces_on_one_plane_leave_no_volume() {
    // cube(10) ∩ (x ≤ 5) ∩ (x ≥ 5), the second half-space turned and turned back.
    let mut dag = Dag::new();
    let block = cube(&mut dag, DVec3::splat(10.0), 0);
    let below = dag.leaf(
        Quadric::half_space(DVec3::splat(5.0), DVec3::X).unwrap(),
        src(1),
    );
    let above = dag.leaf(
        Quadric::half_space(DVec3::new(5.0, 1.0, 2.0), -DVec3::X).unwrap(),
        src(2),
    );
    let turn = DMat4::from_rotation_y(0.3);
    let above = dag.edge(above, &turn.inverse()).unwrap();
    let above = dag.transformed(above, &turn).unwrap();
    let solid = dag.intersection([block.into(), below.into(), above], src(3));
    dag.set_root(solid.into());
    let dnf = build(&dag, Pruning::all());
    assert!(dnf.terms.is_empty(), "{}", dnf.stats);
}

#[test]
fn a_slabs_complement_keeps_the_side_that_a_half_space_on_its_face_leaves() {
    // cube(20) − (5 ≤ z ≤ 10) ∩ (z ≤ 10): the half-space faces the complement across z = 10,
    // but the complement holds both sides of the slab, so z < 5 is left, not nothing.
    let mut dag = Dag::new();
    let block = cube(&mut dag, DVec3::splat(20.0), 0);
    let slab = dag.leaf(
        Quadric::slab(DVec3::new(3.0, 4.0, 7.5), DVec3::Z, 2.5).unwrap(),
        src(1),
    );
    let outside = dag.complement(slab.into(), src(1));
    let below = dag.leaf(
        Quadric::half_space(DVec3::new(1.0, 1.0, 10.0), DVec3::Z).unwrap(),
        src(2),
    );
    let solid = dag.intersection([block.into(), outside.into(), below.into()], src(3));
    dag.set_root(solid.into());
    let dnf = build(&dag, Pruning::all());
    assert_eq!(pass_removed(&dnf), 0, "{}", dnf.stats);
    assert!(dnf.contains(DVec3::new(10.0, 10.0, 2.0)));
    assert!(
        !dnf.contains(DVec3::new(10.0, 10.0, 7.0)) && !dnf.contains(DVec3::new(10.0, 10.0, 15.0))
    );
    // The slab's face and the half-space are one surface, with opposite outward normals.
    let (slab, half) = (
        dnf.quadrics.iter().position(|q| {
            q.quadric.kind() == qcsg_quadric::QuadricKind::ParallelPlanes && q.source == src(1)
        }),
        dnf.quadrics.iter().position(|q| q.source == src(2)),
    );
    let (slab, half) = (slab.unwrap() as u32, half.unwrap() as u32);
    let half_sheet = dnf.surfaces.of(half).unwrap()[0];
    let slab_sheet = dnf
        .surfaces
        .of(slab)
        .unwrap()
        .iter()
        .find(|s| s.surface == half_sheet.surface)
        .copied()
        .unwrap();
    assert_ne!(slab_sheet.orientation, half_sheet.orientation);
    assert!(!slab_sheet.one_sided && half_sheet.one_sided);
    assert!(!dnf.surfaces.meet_only_on_surface(slab, half));
}

#[test]
fn a_flush_notch_keeps_its_terms() {
    // difference() { cube([20, 10, 10]); translate([5, 0, 5]) cube([10, 10, 5]); }: the
    // cutter's z-slab shares the part's top face, but the part below it remains.
    let mut dag = Dag::new();
    let part = cube(&mut dag, DVec3::new(20.0, 10.0, 10.0), 0);
    let cutter = cube(&mut dag, DVec3::new(10.0, 10.0, 5.0), 1);
    let cutter = dag
        .translated(cutter.into(), DVec3::new(5.0, 0.0, 5.0))
        .unwrap();
    let solid = dag.difference([part.into(), cutter], src(2));
    dag.set_root(solid.into());
    let dnf = build(&dag, Pruning::all());
    let unpruned = build(&dag, Pruning::without("final_coincident_pairs").unwrap());
    // The y-slabs are the same quadric: the term of the part's y-slab and the cutter's
    // complement goes; the x and z terms stay.
    assert_eq!(pass_removed(&dnf), unpruned.terms.len() - dnf.terms.len());
    assert_eq!(dnf.terms.len(), 2, "{}", dnf.stats);
    assert!(dnf.contains(DVec3::new(10.0, 5.0, 2.0)) && !dnf.contains(DVec3::new(10.0, 5.0, 7.0)));
    assert!(dnf.contains(DVec3::new(2.0, 5.0, 9.0)));
    // The top face z = 10 is one surface with two sheets on it.
    let top = dnf
        .quadrics
        .iter()
        .enumerate()
        .flat_map(|(i, _)| dnf.surfaces.of(i as u32).unwrap().to_vec())
        .filter(|s| {
            let q = dnf.surfaces.surface(s.surface).unwrap().quadric;
            q.value(DVec3::new(1.0, 1.0, 10.0)).abs() < 1e-12
        })
        .collect::<Vec<_>>();
    assert_eq!(top.len(), 2, "{top:?}");
    assert_eq!(top[0].surface, top[1].surface);
    assert_ne!(top[0].orientation, top[1].orientation);
}

#[test]
fn the_dnf_json_lists_each_quadrics_sheets() {
    let mut dag = Dag::new();
    let part = cube(&mut dag, DVec3::new(20.0, 10.0, 10.0), 0);
    let ball = sphere(&mut dag, 3.0, 1);
    let ball = dag
        .translated(ball.into(), DVec3::new(10.0, 5.0, 10.0))
        .unwrap();
    let solid = dag.difference([part.into(), ball], src(2));
    dag.set_root(solid.into());
    let dnf = build(&dag, Pruning::all());
    let names = vec!["main.qcsg".to_string()];
    let json: serde_json::Value = serde_json::from_str(&qcsg_csg::dnf_to_json(
        &dnf,
        &qcsg_csg::names_from_list(&names),
    ))
    .unwrap();
    let quadrics = json["quadrics"].as_array().unwrap();
    let count = |kind: &str| {
        quadrics
            .iter()
            .filter(|q| q["kind"] == kind)
            .map(|q| q["sheets"].as_array().unwrap().len())
            .collect::<Vec<_>>()
    };
    assert_eq!(count("slab"), vec![2, 2, 2]);
    assert_eq!(count("sphere"), vec![1]);
    for q in quadrics {
        for sheet in q["sheets"].as_array().unwrap() {
            assert!(sheet["surface"].as_u64().unwrap() < dnf.surfaces.len() as u64);
            assert!(sheet["orientation"] == 1 || sheet["orientation"] == -1);
        }
    }
}

#[test]
fn finding_surfaces_stays_near_linear() {
    // 3,000 balls, each with a turned copy, and 3,000 cubes with a turned z-slab and a half-space
    // on its top, scattered over a block: 18,000 quadrics.
    let mut rng = Rng::new(7);
    let mut quadrics = Vec::new();
    for i in 0..6_000 {
        let centre = DVec3::new(1e3 * rng.unit(), 1e3 * rng.unit(), 1e3 * rng.unit());
        let turn = DMat4::from_translation(centre)
            * DMat4::from_rotation_z(rng.unit())
            * DMat4::from_translation(-centre);
        if i % 2 == 0 {
            let ball = Quadric::sphere(centre, 0.5 + rng.unit()).unwrap();
            quadrics.push((ball, Rounding::default()));
            quadrics.push(placed(&ball, &turn));
        } else {
            let half = 0.5 + rng.unit();
            let slab = |n: DVec3| Quadric::slab(centre, n, half).unwrap();
            for n in [DVec3::X, DVec3::Y] {
                quadrics.push((slab(n), Rounding::default()));
            }
            quadrics.push(placed(&slab(DVec3::Z), &turn));
            quadrics.push((
                Quadric::half_space(centre + half * DVec3::Z, DVec3::Z).unwrap(),
                Rounding::default(),
            ));
        }
    }
    let n = quadrics.len();
    let surfaces = surfaces_of(&quadrics);
    // Balls: one surface per pair; cubes: two planes per x, y slab and two for the turned z
    // slab, whose top the half-space shares.
    assert_eq!(surfaces.len(), 3_000 + 3_000 * 6);
    assert!(
        surfaces.comparisons() <= 2 * n,
        "{} comparisons",
        surfaces.comparisons()
    );

    // 3,000 coaxial cylinders of different radii: one grid cell for all, so the comparisons
    // per lookup stop at the cap (a missed merge there costs a speckle, never quadratic time).
    let coaxial: Vec<(Quadric, Rounding)> = (0..3_000)
        .map(|k| {
            let q = Quadric::cylinder(DVec3::ZERO, DVec3::Z, 1.0 + 1e-3 * f64::from(k)).unwrap();
            (q, Rounding::default())
        })
        .collect();
    let surfaces = surfaces_of(&coaxial);
    assert_eq!(surfaces.len(), 3_000);
    assert!(surfaces.comparisons() <= 8 * MAX_CANDIDATES_PER_CELL * coaxial.len());
}
