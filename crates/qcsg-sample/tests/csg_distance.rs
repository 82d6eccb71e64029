//! Layer 2: eq. 22 against brute-force classification. The sign must be right, and within
//! `|d|` of a point along its quadric the classification must not change.

mod common;

use common::{Rng, brute_on_surface, diagonal, points_on, programs_in};
use qcsg_csg::{Aabb, Dnf};
use qcsg_quadric::{DVec3, QuadricKind};
use qcsg_sample::csg_distance::CsgDistance;

/// Checks every literal of every term on random points; returns how many decisive checks ran.
fn check(dnf: &Dnf, seed: u64) -> (usize, usize) {
    let mut rng = Rng::new(seed);
    let (mut decisive, mut neighbours) = (0, 0);
    for (term_index, term) in dnf.terms.iter().enumerate() {
        let half = 0.5 * (term.bounds.max - term.bounds.min) * 1.1;
        let bounds = Aabb::from_centre_half(term.bounds.centre(), half);
        for &quadric in &term.literals {
            let literal = (quadric, term_index as u32);
            let distance = CsgDistance::new(dnf, quadric, term_index as u32);
            let q = dnf.quadrics[quadric as usize].quadric;
            for p in points_on(&q, &bounds, 150, &mut rng) {
                let Some(distance) = &distance else {
                    // No part of the quadric in its term: no point of it is on the surface.
                    let tol = 1e-9 * diagonal(dnf);
                    let truth = brute_on_surface(dnf, quadric, literal.1, p, tol);
                    assert_ne!(truth, Some(true), "{p:?} of {literal:?} is on the surface");
                    decisive += usize::from(truth.is_some());
                    continue;
                };
                let point = (p, distance.distance(p));
                let (d, n) = check_point(dnf, literal, point, &Aabb::EVERYTHING, &mut rng);
                decisive += d;
                neighbours += n;
            }
        }
    }
    (decisive, neighbours)
}

/// Checks `d`, eq. 22 at `p` on `quadric` as a literal of `term`, against brute force: its sign,
/// and that points of the quadric within `|d|` (and `within`) are classified as `p`. Returns
/// whether the point was decisive (0 or 1) and how many neighbours were.
fn check_point(
    dnf: &Dnf,
    (quadric, term): (u32, u32),
    (p, d): (DVec3, f64),
    within: &Aabb,
    rng: &mut Rng,
) -> (usize, usize) {
    let tol = 1e-9 * diagonal(dnf);
    let q = dnf.quadrics[quadric as usize].quadric;
    let planar = matches!(q.kind(), QuadricKind::Plane | QuadricKind::ParallelPlanes);
    let Some(truth) = brute_on_surface(dnf, quadric, term, p, tol) else {
        return (0, 0);
    };
    if d != 0.0 {
        assert_eq!(
            d < 0.0,
            truth,
            "sign at {p:?}: d = {d}, term {term}, quadric {quadric}"
        );
    }
    let mut neighbours = 0;
    // Points of the same quadric within |d| share the classification.
    for _ in 0..8 {
        let offset = rng.direction() * rng.range(0.0, 0.95 * d.abs());
        let moved = p + offset;
        let Some(n) = q.normal(moved) else { continue };
        let Some(t) = q
            .intersect_line(moved, n)
            .roots()
            .into_iter()
            .min_by(|a, b| a.abs().total_cmp(&b.abs()))
        else {
            continue;
        };
        let nearby = moved + t * n;
        if (nearby - p).length() >= d.abs() || !within.contains(nearby) {
            continue;
        }
        // A planar quadric's claim is for the sheet of `p`: eq. 22 sees each sheet on its own,
        // and a basic region lies on one.
        let other_sheet = planar
            && q.normal(nearby)
                .zip(q.normal(p))
                .is_none_or(|(a, b)| a.dot(b) <= 0.0);
        if other_sheet {
            continue;
        }
        if let Some(near_truth) = brute_on_surface(dnf, quadric, term, nearby, tol) {
            neighbours += 1;
            assert_eq!(
                near_truth, truth,
                "classification changed within |d| = {d}: {p:?} -> {nearby:?}"
            );
        }
    }
    (1, neighbours)
}

#[test]
fn three_spheres_classification() {
    let (decisive, neighbours) = check(&common::three_spheres(), 1);
    assert!(
        decisive > 200 && neighbours > 200,
        "{decisive} {neighbours}"
    );
}

#[test]
fn cube_minus_cylinder_classification() {
    let (decisive, neighbours) = check(&common::cube_minus_cylinder(), 2);
    assert!(
        decisive > 200 && neighbours > 200,
        "{decisive} {neighbours}"
    );
}

#[test]
fn cone_slab_and_tangent_spheres_classification() {
    let (decisive, _) = check(&common::cone_slab(), 3);
    assert!(decisive > 100);
    let (decisive, _) = check(&common::tangent_spheres(), 4);
    assert!(decisive > 100);
}

/// Surfaces that touch planes without crossing them, cylinders cut by planes through their
/// axes, cones and cylinders whose rims meet on a plane, nearly parallel planes: the tangency,
/// section and one-sided-slab rules of eq. 22 (the rounded rectangles of OpenSCAD models,
/// upright and tilted, a rod on a plate, and the scenes and examples built of them).
#[test]
fn tangent_and_sectioned_classification() {
    let programs = [
        "tests/stability/tangent_rounded_slab.qcsg",
        "tests/stability/tangent_rounded_tray.qcsg",
        "tests/stability/tangent_rounded_tray_tilted.qcsg",
        "tests/stability/tangent_cylinder_on_face.qcsg",
        "tests/stability/parallel_planes.qcsg",
        "tests/stability/hyperboloid_two_sheets_gap.qcsg",
        "tests/stability/coincident_difference_flush.qcsg",
        "tests/stability/coincident_difference_flush_tilted.qcsg",
        "examples/customizer_box.qcsg",
        "examples/openscad_bracket.scad",
        "examples/chess_bishop.qcsg",
        "examples/modifiers.qcsg",
        "examples/precision_part.qcsg",
        "examples/rocket.qcsg",
    ];
    for (seed, program) in programs.into_iter().enumerate() {
        let dnf = common::compile_file(&common::workspace_root().join(program)).expect(program);
        let (decisive, neighbours) = check(&dnf, 10 + seed as u64);
        assert!(
            decisive > 300 && neighbours > 300,
            "{program}: {decisive} {neighbours}"
        );
    }
}

/// Eq. 22 of a part leaves out the parts farther from it than its box's diagonal ("Far
/// terms"). It must still be right inside and around each part, and each part must see only
/// its neighbours (else this tests nothing, and setup grows with the square of the parts).
#[test]
fn far_terms_left_out_classification() {
    let path = common::workspace_root().join("tests/stability/many_parts.qcsg");
    let dnf = common::compile_file(&path).expect("many_parts");
    let (decisive, neighbours) = check(&dnf, 40);
    assert!(
        decisive > 2000 && neighbours > 2000,
        "{decisive} {neighbours}"
    );
    // A part sees its ring of neighbours, and the plate, the bar and the rail the parts
    // along them: a few terms per literal on average (all 73 others and their unions without
    // the rule).
    let literals: usize = dnf.terms.iter().map(|t| t.literals.len()).sum();
    let mut seen = 0;
    for (term_index, term) in dnf.terms.iter().enumerate() {
        for &quadric in &term.literals {
            let distance = CsgDistance::new(&dnf, quadric, term_index as u32).expect("indices");
            seen += distance.other_terms();
        }
    }
    assert!(
        seen < 8 * literals,
        "{seen} terms seen by {literals} literals"
    );
}

/// Eq. 22 for a small part of a plate drilled with many holes (one term of many literals)
/// leaves out the holes far from the part ("Far literals"), and a box's distance narrowed to
/// a smaller box leaves out more: both must stay right on the part and the smaller box, at
/// points inside them and just outside.
#[test]
fn far_literals_classification() {
    let path = common::workspace_root().join("tests/stability/perforated_plate.qcsg");
    let dnf = common::compile_file(&path).expect("perforated_plate");
    let term = &dnf.terms[0];
    assert!(term.literals.len() > 100, "one term of many literals");
    let mut rng = Rng::new(50);
    let (mut decisive, mut neighbours, mut left_out) = (0, 0, 0);
    for &quadric in term.literals.iter().step_by(7) {
        let q = dnf.quadrics[quadric as usize].quadric;
        for _ in 0..4 {
            // A part around a point of the quadric in the plate's box, and a quarter of it.
            let Some(&centre) = points_on(&q, &term.bounds, 1, &mut rng).first() else {
                continue;
            };
            let half = DVec3::splat(rng.range(0.5, 4.0));
            let part = Aabb::from_centre_half(centre, half);
            let quarter = Aabb::from_centre_half(centre, 0.25 * half);
            let distance = CsgDistance::for_part(&dnf, quadric, 0, &part).expect("indices");
            let size = |b: &Aabb| (b.max - b.min).length();
            let near = distance.near(&part, size(&part) + 0.1);
            let narrow = near.narrow(&quarter, size(&quarter) + 0.1);
            left_out += usize::from(
                distance.other_terms() == 0 && near.literals_of_large_terms() < term.literals.len(),
            );
            // The claims hold for the quadric's points inside the part.
            for p in points_on(&q, &part, 40, &mut rng) {
                let mut checks = vec![distance.distance(p), near.distance(p)];
                if quarter.contains(p) {
                    checks.push(narrow.distance(p));
                }
                for d in checks {
                    let (d, n) = check_point(&dnf, (quadric, 0), (p, d), &part, &mut rng);
                    decisive += d;
                    neighbours += n;
                }
            }
        }
    }
    assert!(
        decisive > 1000 && neighbours > 1000 && left_out > 20,
        "{decisive} {neighbours} {left_out}"
    );
}

/// Surfaces a small gap apart (nested balls `1e-9` apart, thin spherical shells, a column whose
/// surface lies `0.01` inside the hole of every step around it): a literal whose square part is
/// a multiple of the sampled quadric's holds on all of it or on none ("Offset surfaces"). Eq. 22
/// must stay right there, and it must see past the gap: the inner ball of the union lies
/// `1e-9` inside the outer one, which the distance to the outer sphere alone cannot tell.
#[test]
fn offset_surfaces_classification() {
    // OpenSCAD's overlaps by a small epsilon: a tube around a pin 0.01 thinner than its bore, a
    // ball 1e-3 inside another, a cup whose bore reaches 0.01 past its rim.
    let epsilons =
        "difference() { cylinder(h = 10, r = 5); translate([0, 0, -1]) cylinder(h = 12, r = 4); }
        cylinder(h = 10, r = 3.99);
        translate([12, 0, 0]) { sphere(3); sphere(3 - 1e-3); }
        translate([0, 12, 0]) difference() { sphere(3); translate([0, 0, 1]) sphere(2.99); }";
    let mut scenes = vec![(
        "epsilons".to_string(),
        common::compile_text("epsilons.qcsg", epsilons.to_string()).expect("epsilons"),
    )];
    for program in [
        "tests/stability/thin_wall_shell.qcsg",
        "examples/spiral_staircase.qcsg",
    ] {
        let path = common::workspace_root().join(program);
        scenes.push((
            program.to_string(),
            common::compile_file(&path).expect(program),
        ));
    }
    for (seed, (name, dnf)) in scenes.iter().enumerate() {
        let (decisive, neighbours) = check(dnf, 60 + seed as u64);
        assert!(
            decisive > 300 && neighbours > 100,
            "{name}: {decisive} {neighbours}"
        );
    }
    let path = common::workspace_root().join("tests/stability/nested_spheres_union.qcsg");
    let dnf = common::compile_file(&path).expect("nested_spheres_union");
    let mut rng = Rng::new(70);
    let radius = |quadric: u32| {
        let frame = dnf.quadrics[quadric as usize].quadric.frame();
        (-frame.constant / frame.eigenvalues[0]).sqrt()
    };
    let (inner, term) = (dnf.terms.iter().enumerate())
        .map(|(t, term)| (term.literals[0], t as u32))
        .min_by(|a, b| radius(a.0).total_cmp(&radius(b.0)))
        .expect("two balls");
    let q = dnf.quadrics[inner as usize].quadric;
    let distance = CsgDistance::new(&dnf, inner, term).expect("indices");
    for p in points_on(&q, &dnf.bounds, 50, &mut rng) {
        let d = distance.distance(p);
        assert!(
            d > 0.1,
            "the inner ball's surface at {p} is hidden by only {d}"
        );
    }
}

/// Surfaces that touch along a curve or at a point, or nest: a ball and a cylinder of its
/// radius (the rounded end of a capsule, turned or not), a cup hollowed by the same shapes
/// `0.05` smaller, a ball touching the inside of another at a point ("Touching surfaces").
/// Eq. 22 must stay right there, and it must see past the contact: the capsule's ball is hidden
/// inside the cylinder by about its height above the cylinder's cap, where the distance to the
/// cylinder's side alone is only `z² / 2r`, and a ball inside an ellipsoid `1e-9` longer
/// (which brute force cannot tell apart) and an ellipsoid touching the inside of another turned
/// differently are hidden everywhere.
#[test]
fn touching_surfaces_classification() {
    let capsule = "cylinder(h = 24, r = 10);\nsphere(10);";
    let scenes = [
        ("capsule", capsule.to_string()),
        (
            "turned capsule",
            format!("rotate([30, 40, 10]) {{ {capsule} }}"),
        ),
        (
            "cup",
            "difference() {
                union() { cylinder(h = 24, r = 10); sphere(10); }
                union() { cylinder(h = 25, r = 9.95); sphere(9.95); }
            }"
            .to_string(),
        ),
        (
            "inner ball",
            "sphere(2);\ntranslate([1, 0, 0]) sphere(1);".to_string(),
        ),
    ];
    for (seed, (name, text)) in scenes.into_iter().enumerate() {
        let dnf = common::compile_text("touching.qcsg", text).expect(name);
        let (decisive, _) = check(&dnf, 80 + seed as u64);
        assert!(decisive >= 250, "{name}: {decisive}");
    }
    // The inner of two solids, a term of its own, and how far eq. 22 must put each of its
    // points off the surface.
    type LeastDistance = fn(DVec3) -> Option<f64>;
    let hidden: [(&str, LeastDistance); 3] = [
        (capsule, |p| (p.z >= 1.0).then_some(0.5 * p.z)),
        ("sphere(1);\nscale([1, 1, 1 + 1e-9]) sphere(1);", |_| {
            Some(0.1)
        }),
        // Ellipsoids turned differently, the inner touching the outer at its tips: no axes in
        // common, so the S-lemma's search finds the multiple.
        (
            "scale([3, 2, 2.5]) sphere(1);\nrotate([30, 0, 0]) scale([3, 1, 1.5]) sphere(1);",
            |_| Some(1.0),
        ),
    ];
    for (seed, (text, least)) in hidden.into_iter().enumerate() {
        let dnf = common::compile_text("hidden.qcsg", text.to_string()).expect(text);
        let alone: Vec<(u32, u32)> = (dnf.terms.iter().enumerate())
            .filter(|(_, term)| term.literals.len() == 1)
            .map(|(t, term)| (term.literals[0], t as u32))
            .collect();
        let quadric = |i: u32| dnf.quadrics[i as usize].quadric;
        let inside_another = |&&(i, _): &&(u32, u32)| {
            let mut rng = Rng::new(1);
            let p = points_on(&quadric(i), &dnf.bounds, 1, &mut rng)[0];
            dnf.terms
                .iter()
                .flat_map(|t| &t.literals)
                .any(|&j| j != i && quadric(j).value(p) < 0.0)
        };
        let &(inner, term) = alone
            .iter()
            .find(inside_another)
            .expect("the inner solid's term");
        let distance = CsgDistance::new(&dnf, inner, term).expect("indices");
        let mut rng = Rng::new(90 + seed as u64);
        let mut checked = 0;
        for p in points_on(&quadric(inner), &dnf.bounds, 200, &mut rng) {
            if let Some(least) = least(p) {
                let d = distance.distance(p);
                assert!(
                    d >= least,
                    "{text}: the inner surface at {p} is hidden by only {d}"
                );
                checked += 1;
            }
        }
        assert!(checked > 20, "{text}: {checked} points checked");
    }
}

/// Random capsules, cones capped by balls, hollowed cups and pairs of ellipsoids, turned and
/// moved at random: the touching rule's axes, ratios and S-lemma search must hold whichever
/// way the parts lie ("Touching surfaces").
#[test]
fn random_touching_surfaces_classification() {
    let mut rng = Rng::new(100);
    for case in 0..16 {
        let (r, h) = (rng.range(0.5, 5.0), rng.range(1.0, 20.0));
        let wall = r * rng.range(1e-3, 0.2);
        let turn = [0, 1, 2].map(|_| rng.range(-180.0, 180.0));
        let at = rng.direction() * rng.range(0.0, 100.0);
        let axes = |rng: &mut Rng| [0, 1, 2].map(|_| rng.range(0.5, 3.0));
        let part = match case % 4 {
            // Two ellipsoids turned differently, nested or crossing (the S-lemma's case).
            3 => {
                let (outer, inner) = (axes(&mut rng), axes(&mut rng));
                let spin = [0, 1, 2].map(|_| rng.range(-90.0, 90.0));
                let shift = rng.direction() * rng.range(0.0, 0.5);
                format!(
                    "scale({outer:?}) sphere(1); translate([{}, {}, {}]) rotate({spin:?}) \
                     scale({inner:?}) sphere(1);",
                    shift.x, shift.y, shift.z
                )
            }
            0 => format!(
                "cylinder(h = {h}, r = {r}); sphere({r}); translate([0, 0, {h}]) sphere({r});"
            ),
            // A ball of the cone's radius where the cone's side is steep enough to meet it only
            // at its rim, and one inside the cone touching its side along a circle.
            1 => format!(
                "cylinder(h = {h}, r1 = {r}, r2 = 0); sphere({r}); \
                 translate([0, 0, {h} / 2]) sphere({r} / 2 * {h} / sqrt({h} * {h} + {r} * {r}));"
            ),
            _ => format!(
                "difference() {{ union() {{ cylinder(h = {h}, r = {r}); sphere({r}); }} \
                 union() {{ cylinder(h = {h} + 1, r = {r} - {wall}); sphere({r} - {wall}); }} }}"
            ),
        };
        let text = format!(
            "translate([{}, {}, {}]) rotate([{}, {}, {}]) {{ {part} }}",
            at.x, at.y, at.z, turn[0], turn[1], turn[2]
        );
        let dnf = common::compile_text("random.qcsg", text.clone()).expect("random touching");
        let (decisive, _) = check(&dnf, 200 + case);
        assert!(decisive >= 250, "{text}: {decisive}");
    }
}

/// Gussets cut from a box by a box turned 45° about their edge, as OpenSCAD models make them,
/// turned at random: the term of the cutter's face that misses the gusset has only a line on the
/// gusset's bottom plane, which eq. 22 must see as no area ("Strips of no width").
#[test]
fn strips_of_no_width_classification() {
    let mut rng = Rng::new(300);
    for case in 0..6 {
        let (a, w) = (rng.range(5.0, 30.0), rng.range(1.0, 6.0));
        let turn = [0, 1, 2].map(|_| {
            if case == 0 {
                0.0
            } else {
                rng.range(-180.0, 180.0)
            }
        });
        let text = format!(
            "rotate([{}, {}, {}]) difference() {{
                cube([{w}, {a}, {a}]);
                translate([-1, {a}, 0]) rotate([45, 0, 0]) cube([{w} + 2, {a} * 2, {a} * 2]);
            }}",
            turn[0], turn[1], turn[2]
        );
        let dnf = common::compile_text("gusset.qcsg", text.clone()).expect("gusset");
        let (decisive, _) = check(&dnf, 300 + case);
        assert!(decisive >= 250, "{text}: {decisive}");
    }
}

#[test]
fn box_distance_is_exact() {
    let b = Aabb::new(DVec3::ZERO, DVec3::ONE);
    let d = qcsg_sample::csg_distance::box_distance;
    assert_eq!(d(&b, DVec3::splat(0.5)), -0.5);
    assert_eq!(d(&b, DVec3::new(2.0, 0.5, 0.5)), 1.0);
    assert!((d(&b, DVec3::new(2.0, 2.0, 0.5)) - 2f64.sqrt()).abs() < 1e-15);
}

/// Claims eq. 22 of a box makes for all of it, before any query, checked by brute force over
/// every stability scene and the examples, for boxes of many sizes around points of every
/// literal: where it is nowhere negative (the sampler leaves the basic region out), no point of
/// the sampled quadric in the box is on the surface, and eq. 22 is negative at none; where
/// every point is on the surface (the sampler fills the region without a query), none is off
/// it. Both claims must be made often enough to matter.
#[test]
fn patch_claims_hold() {
    let files = [programs_in("tests/stability"), programs_in("examples")].concat();
    let mut rng = Rng::new(60);
    let (mut off_claims, mut on_claims, mut checked) = (0, 0, 0);
    for path in &files {
        let Ok(dnf) = common::compile_file(path) else {
            continue;
        };
        let size = diagonal(&dnf);
        if !size.is_finite() {
            continue;
        }
        let tol = 1e-9 * size;
        for (term_index, term) in dnf.terms.iter().enumerate() {
            let term_index = term_index as u32;
            for &quadric in &term.literals {
                let q = dnf.quadrics[quadric as usize].quadric;
                for centre in points_on(&q, &term.bounds, 6, &mut rng) {
                    let half = DVec3::splat(size * rng.range(0.002, 0.2));
                    let part = Aabb::from_centre_half(centre, half);
                    let Some(distance) = CsgDistance::for_part(&dnf, quadric, term_index, &part)
                    else {
                        continue;
                    };
                    let near = distance.near(&part, 2.0 * (part.max - part.min).length());
                    let off = near.nowhere_negative(&part);
                    let on = near.everywhere_on_surface(&part);
                    assert!(!(off && on), "{path:?}: both claims for {part:?}");
                    if !(off || on) {
                        continue;
                    }
                    off_claims += usize::from(off);
                    on_claims += usize::from(on);
                    for p in points_on(&q, &part, 20, &mut rng) {
                        let d = near.distance(p);
                        assert!(
                            !off || d >= 0.0,
                            "{path:?}: eq. 22 is {d} at {p:?} in {part:?}"
                        );
                        let truth = brute_on_surface(&dnf, quadric, term_index, p, tol);
                        assert_ne!(
                            truth,
                            Some(!on),
                            "{path:?}: {p:?} of quadric {quadric}, term {term_index}, in {part:?}"
                        );
                        checked += 1;
                    }
                }
            }
        }
    }
    assert!(
        off_claims > 500 && on_claims > 250 && checked > 10000,
        "{off_claims} and {on_claims} claims, {checked} points"
    );
}
