//! Text subtracted from a part (engraving): the DNF expands the text's recorded complement, its
//! unfilled cells, so its size follows the glyphs' cells instead of multiplying out, and it is the
//! same solid as the DAG with the same curved faces.

mod common;

use common::eval;
use glam::DVec3;
use qcsg_csg::dnf::Pruning;
use qcsg_csg::{Dnf, DnfOptions, build_dnf};
use qcsg_quadric::QuadricKind;
use qcsg_testkit::Rng;

const PLATE: &str = "cube([92, 20, 4]);";
const TEXT: &str = "text(\"Engraved: qcsg & 2026!\", size = 7)";

fn engraved(text: &str) -> String {
    format!("difference() {{ {PLATE} translate([3, 5, 2]) linear_extrude(3) {text}; }}")
}

fn dnf_of(source: &str) -> (qcsg_eval::Evaluation, Dnf) {
    let e = eval(source);
    assert!(!e.has_errors(), "{source}: {:?}", e.diagnostics);
    let dnf = build_dnf(&e.dag, &DnfOptions::default()).expect("within the term limit");
    (e, dnf)
}

#[test]
fn engraved_text_has_about_as_many_terms_as_raised_text() {
    let (_, raised) = dnf_of(&format!("translate([3, 5, 2]) linear_extrude(3) {TEXT};"));
    let (_, cut) = dnf_of(&engraved(TEXT));
    assert!(
        cut.terms.len() <= 4 * raised.terms.len() + 16,
        "{} terms engraved, {} raised",
        cut.terms.len(),
        raised.terms.len()
    );
    // Near-linear: four times the text, about four times the terms.
    let terms = |repeat: usize| {
        let line = "Sphinx of black quartz. ".repeat(repeat);
        let plate = format!(
            "difference() {{ cube([{}, 12, 3]); translate([2, 3, 1]) linear_extrude(3) text(\"{line}\", size = 5); }}",
            4.0 + 90.0 * repeat as f64
        );
        dnf_of(&plate).1.terms.len()
    };
    let (one, four) = (terms(1), terms(4));
    assert!(four <= 5 * one, "{one} terms, then {four}");
}

#[test]
fn engraved_text_is_the_dags_solid() {
    let scene = engraved(TEXT);
    // Points over the plate and around it, and three times as many where the letters are cut.
    let around = (DVec3::new(-2.0, -2.0, -1.0), DVec3::new(94.0, 22.0, 5.0));
    let letters = (DVec3::new(2.0, 3.0, 1.9), DVec3::new(90.0, 14.0, 4.0));
    let (in_around, out_around) = dnf_agrees_with_the_dag(&scene, 40, 10_000, Some(around));
    let (in_letters, out_letters) = dnf_agrees_with_the_dag(&scene, 41, 30_000, Some(letters));
    let (inside, outside) = (in_around + in_letters, out_around + out_letters);
    assert!(
        inside > 1000 && outside > 1000,
        "{inside} in, {outside} out"
    );
}

#[test]
fn engraved_faces_are_the_glyphs_own_parabolas() {
    // Every parabola of the raised text, none pruned away.
    let e = eval(&format!("translate([3, 5, 2]) linear_extrude(3) {TEXT};"));
    let unpruned = DnfOptions {
        prune: false,
        pruning: Pruning::none(),
        ..DnfOptions::default()
    };
    let raised = build_dnf(&e.dag, &unpruned).expect("a union of cells");
    let (_, cut) = dnf_of(&engraved(TEXT));
    // A parabolic cylinder up to sign, bit for bit.
    let key = |q: &qcsg_quadric::Quadric| {
        let k = q.coefficients();
        let s = if k.iter().find(|v| **v != 0.0).is_some_and(|v| *v < 0.0) {
            -1.0
        } else {
            1.0
        };
        let mut bits: Vec<u64> = k.iter().map(|v| (s * v + 0.0).to_bits()).collect();
        bits.extend(q.origin().to_array().map(|v| (v + 0.0).to_bits()));
        bits
    };
    let parabolas = |dnf: &Dnf| -> std::collections::HashSet<Vec<u64>> {
        dnf.terms
            .iter()
            .flat_map(|t| t.literals.iter())
            .map(|&l| &dnf.quadrics[l as usize].quadric)
            .filter(|q| q.kind() == QuadricKind::ParabolicCylinder)
            .map(key)
            .collect()
    };
    let (raised, cut) = (parabolas(&raised), parabolas(&cut));
    assert!(raised.len() > 50, "{} parabolas", raised.len());
    let foreign: Vec<_> = cut.difference(&raised).collect();
    assert!(
        foreign.is_empty(),
        "{} parabolas not the glyphs'",
        foreign.len()
    );
}

#[test]
fn text_in_a_union_subtracted_and_intersected_keeps_its_meaning() {
    // The complement stands in only where the text is subtracted; a union of two texts, text
    // intersected with a part and text subtracted twice all still agree with the DAG.
    let scenes = [
        "difference() { cube([40, 14, 3]); translate([1, 2, 1]) linear_extrude(3) { text(\"AB\", size = 8); translate([14, 0]) text(\"ob\", size = 8); } }",
        "intersection() { cube([40, 14, 3]); translate([1, 2, -1]) linear_extrude(5) text(\"Wg8\", size = 9); }",
        "difference() { cube([40, 14, 3]); linear_extrude(5) difference() { square([40, 14]); translate([1, 2]) text(\"R&D\", size = 9); } }",
    ];
    for (n, scene) in scenes.iter().enumerate() {
        let around = (DVec3::new(-1.0, -1.0, -1.0), DVec3::new(41.0, 15.0, 4.0));
        dnf_agrees_with_the_dag(scene, n as u64, 10_000, Some(around));
    }
}

/// Checks at `count` random points (in `within`, else the solid's box) that the DNF of `scene`
/// holds the points the DAG does; returns how many were inside and outside.
fn dnf_agrees_with_the_dag(
    scene: &str,
    seed: u64,
    count: usize,
    within: Option<(DVec3, DVec3)>,
) -> (usize, usize) {
    let (e, dnf) = dnf_of(scene);
    let (lo, hi) = within.unwrap_or_else(|| {
        let b = e.dag.edge_bounds(e.dag.root().expect("a solid"));
        (b.min, b.max)
    });
    let mut rng = Rng::new(seed);
    let (mut inside, mut outside) = (0, 0);
    for _ in 0..count {
        let p = rng.in_box(lo, hi);
        let expected = e.dag.contains(p);
        assert_eq!(dnf.contains(p), expected, "{scene} at {p}");
        if expected {
            inside += 1;
        } else {
            outside += 1;
        }
    }
    (inside, outside)
}

#[test]
fn glyphs_built_together_and_vertical_text_keep_their_meaning() {
    // Tight spacing makes glyph boxes overlap, so neighbours are built together in one frame;
    // vertical text runs along y; repeats are placed copies. Everywhere the engraved DNF, built
    // from the text's complement, is the DAG's solid.
    let scenes = [
        "difference() { cube([40, 14, 3]); translate([1, 3, 1]) linear_extrude(3) text(\"AV o AVAV fi o\", size = 5, spacing = 0.8); }",
        "difference() { cube([14, 60, 3]); translate([7, 58, 1]) linear_extrude(3) text(\"qcsgq\", size = 8, direction = \"ttb\"); }",
        "difference() { cube([90, 12, 3]); translate([1, 3, 1]) linear_extrude(3) text(\"oooo xo ox oo\", size = 8); }",
    ];
    for (n, scene) in scenes.iter().enumerate() {
        let (inside, outside) = dnf_agrees_with_the_dag(scene, 100 + n as u64, 20_000, None);
        assert!(
            inside > 1000 && outside > 1000,
            "{scene}: {inside} in, {outside} out"
        );
    }
}
