//! `text()`: glyph boundaries exactly where the font file puts them, OpenSCAD's metrics, fonts
//! by name, and the diagnostics of unusable input.

mod common;

use common::{codes, eval, membership, p};
use glam::{DVec2, DVec3};
use qcsg_csg::{DnfOptions, build_dnf};
use qcsg_eval::glyphs::layout::{HAlign, TextParams, VAlign, layout};
use qcsg_mesh::curved::{FillRule, Segment, curved_cells};
use qcsg_testkit::Rng;

/// The bundled font, read straight from the crate's folder.
const SANS: &[u8] = include_bytes!("../fonts/LiberationSans-Regular.ttf");

/// A glyph's outline read with ttf-parser's callbacks: its quadratic arcs and its lines, in font
/// units.
#[derive(Default)]
struct Pieces {
    pen: (f32, f32),
    arcs: Vec<[(f32, f32); 3]>,
    lines: Vec<[(f32, f32); 2]>,
}

impl ttf_parser::OutlineBuilder for Pieces {
    fn move_to(&mut self, x: f32, y: f32) {
        self.pen = (x, y);
    }
    fn line_to(&mut self, x: f32, y: f32) {
        self.lines.push([self.pen, (x, y)]);
        self.pen = (x, y);
    }
    fn quad_to(&mut self, x1: f32, y1: f32, x: f32, y: f32) {
        self.arcs.push([self.pen, (x1, y1), (x, y)]);
        self.pen = (x, y);
    }
    fn curve_to(&mut self, _: f32, _: f32, _: f32, _: f32, x: f32, y: f32) {
        self.pen = (x, y);
    }
    fn close(&mut self) {}
}

fn pieces(c: char) -> (Pieces, f64) {
    let face = ttf_parser::Face::parse(SANS, 0).unwrap();
    let mut pieces = Pieces::default();
    face.outline_glyph(face.glyph_index(c).unwrap(), &mut pieces)
        .unwrap();
    (pieces, f64::from(face.units_per_em()))
}

#[test]
fn points_on_a_glyphs_parabolic_arcs_are_on_the_solids_surface() {
    // OpenSCAD's scale: one em is size / 0.72 units, and the first glyph's origin is the origin.
    let size = 10.0;
    for c in ['S', 'e', 'O', '&', '3'] {
        let (pieces, upem) = pieces(c);
        assert!(pieces.arcs.len() >= 4, "{c} has arcs");
        let scale = size / 0.72 / upem;
        let at = |(x, y): (f32, f32)| DVec2::new(f64::from(x), f64::from(y)) * scale;
        let e = eval(&format!("linear_extrude(2) text(\"{c}\", size = {size});"));
        assert!(!e.has_errors(), "{:?}", e.diagnostics);
        let dnf = build_dnf(&e.dag, &DnfOptions::default()).unwrap();
        let mut checked = 0;
        for arc in &pieces.arcs {
            let [p0, p1, p2] = arc.map(at);
            for t in [0.17, 0.5, 0.83] {
                let s = 1.0 - t;
                let point = p0 * (s * s) + p1 * (2.0 * s * t) + p2 * (t * t);
                let tangent = (p1 - p0) * (2.0 * s) + (p2 - p1) * (2.0 * t);
                if tangent.length() < 1e-9 {
                    continue;
                }
                let normal = tangent.perp().normalize();
                // Across the arc membership changes within a hair's breadth, on both forms.
                let eps = 1e-7;
                let (a, b) = (point + normal * eps, point - normal * eps);
                let a3 = DVec3::new(a.x, a.y, 1.0);
                let b3 = DVec3::new(b.x, b.y, 1.0);
                assert_ne!(
                    e.dag.contains(a3),
                    e.dag.contains(b3),
                    "{c}: arc point {point}"
                );
                assert_ne!(dnf.contains(a3), dnf.contains(b3), "{c}: arc point {point}");
                // And not a little further: the boundary is the arc, not near it.
                let (a, b) = (point + normal * 1e-3, point - normal * 1e-3);
                assert_ne!(
                    dnf.contains(DVec3::new(a.x, a.y, 1.0)),
                    dnf.contains(DVec3::new(b.x, b.y, 1.0))
                );
                checked += 1;
            }
        }
        assert!(checked >= 12, "{c}: {checked} points");
    }
}

#[test]
fn advances_kerning_and_alignment_follow_openscad() {
    // Measured from `openscad -o x.svg` (OpenSCAD 2021.01): "HH" at size 10 puts the second
    // H's left stem at x = 10.9343; "AV" kerns V by -152 font units to x = 8.04; "HH" centred
    // has its first stem at x = -8.65572 and the baseline at y = -4.66562.
    membership(
        "text(\"HH\", size = 10);",
        &[
            (p(10.95, 5.0, 0.0), true),
            (p(10.92, 5.0, 0.0), false),
            (p(1.15, 5.0, 0.0), true),
            (p(1.13, 5.0, 0.0), false),
            (p(5.0, 4.9, 0.0), true),
            (p(5.0, 4.4, 0.0), false),
        ],
    );
    membership(
        "text(\"HH\", size = 10, halign = \"center\", valign = \"center\");",
        &[
            (p(-8.64, 0.0, 0.0), true),
            (p(-8.67, 0.0, 0.0), false),
            (p(-8.0, -4.65, 0.0), true),
            (p(-8.0, -4.68, 0.0), false),
        ],
    );
    // "AV": V kerned by -152 font units; OpenSCAD puts V's top-right corner at x = 17.2422.
    membership(
        "text(\"AV\", size = 10);",
        &[(p(17.21, 9.5, 0.0), true), (p(17.27, 9.5, 0.0), false)],
    );
}

#[test]
fn fonts_are_found_by_fontconfig_names() {
    // The bundled font draws "I" as one bar whatever is installed; an unknown family warns.
    let found = membership(
        "text(\"I\", font = \"No Such Family\");",
        &[(p(1.6, 5.0, 0.0), true), (p(4.0, 5.0, 0.0), false)],
    );
    assert!(found.contains(&"W0566"), "{found:?}");
    // Bold is wider than regular where fonts are installed (the bundled font has no bold, so
    // on a bare machine both are the regular face and the test only checks no warning).
    let e = eval("text(\"l\", font = \"Liberation Sans:style=Bold\");");
    assert!(!e.has_errors());
}

#[test]
fn empty_tiny_huge_and_unknown_input_are_diagnostics_or_nothing() {
    // (W0560 is the top level's note that a 2-D shape is shown as a plate.)
    let warnings = |text: &str| -> Vec<&'static str> {
        codes(&eval(text))
            .into_iter()
            .filter(|&c| c != "W0560")
            .collect()
    };
    assert!(warnings("text(\"\");").is_empty());
    assert_eq!(warnings("text(\"a\", size = 0);"), vec!["W0553"]);
    assert_eq!(warnings("text(\"a\", size = -3);"), vec!["W0553"]);
    assert_eq!(warnings("text(\"a\", halign = \"middle\");"), vec!["W0552"]);
    // A character the font lacks draws its missing-glyph box, with a warning.
    assert_eq!(warnings("text(\"\u{4e2d}\");"), vec!["W0567"]);
    // Beyond the supported magnitude: an error at size, never a panic.
    let e = eval("text(\"a\", size = 1e200);");
    assert_eq!(codes(&e), vec!["E0552"]);
    // Far below rounding: nothing, or a tiny glyph, but no panic.
    let e = eval("text(\"a\", size = 1e-300);");
    assert!(!e.has_errors());
    // Right to left: the glyphs in reverse order, first from the origin.
    membership(
        "text(\"HI\", size = 10, direction = \"rtl\");",
        &[(p(1.5, 5.0, 0.0), true)],
    );
}

#[test]
fn a_paragraph_stays_near_linear() {
    // Four times the text gives about four times the terms: each glyph's cells are its own.
    let terms = |repeat: usize| {
        let paragraph = "The quick brown fox jumps over the lazy dog. ".repeat(repeat);
        let e = eval(&format!(
            "linear_extrude(1) text(\"{paragraph}\", size = 5);"
        ));
        assert!(!e.has_errors());
        build_dnf(&e.dag, &DnfOptions::default())
            .unwrap()
            .terms
            .len()
    };
    let (one, four) = (terms(1), terms(4));
    assert!(four <= 4 * one + 8, "{one} terms, then {four}");
}

#[test]
fn a_repeated_glyph_is_built_once() {
    // Each glyph repeated is placed again, not built again: a few nodes for its place in the
    // text and its complement, where a glyph built anew takes hundreds.
    let line = "abcdefghijklmnopqrs";
    let nodes = |repeat: usize| {
        let e = eval(&format!(
            "linear_extrude(2) text(\"{}\");",
            line.repeat(repeat)
        ));
        assert!(!e.has_errors());
        e.dag.len()
    };
    let (one, hundred) = (nodes(1), nodes(100));
    let added = hundred - one;
    assert!(
        added <= 4 * 99 * line.len(),
        "{one} nodes for one line, {hundred} for a hundred"
    );
}

/// The winding number at `q` of contours with every arc cut into `n` chords.
fn flattened_winding(contours: &[Vec<Segment>], q: DVec2, n: usize) -> (i32, f64) {
    let mut w = 0;
    let mut distance = f64::INFINITY;
    let mut edge = |a: DVec2, b: DVec2| {
        let t = ((q - a).dot(b - a) / (b - a).length_squared().max(1e-300)).clamp(0.0, 1.0);
        distance = distance.min((a + (b - a) * t).distance(q));
        if (a.y <= q.y) != (b.y <= q.y) {
            let t = (q.y - a.y) / (b.y - a.y);
            if a.x + t * (b.x - a.x) > q.x {
                w += if b.y > a.y { 1 } else { -1 };
            }
        }
    };
    for contour in contours {
        for s in contour {
            match *s {
                Segment::Line(a, b) => edge(a, b),
                Segment::Quad(a, c, b) => {
                    let arc = qcsg_mesh::curved::BezierArc {
                        p0: a,
                        p1: c,
                        p2: b,
                    };
                    for k in 0..n {
                        edge(
                            arc.point(k as f64 / n as f64),
                            arc.point((k + 1) as f64 / n as f64),
                        );
                    }
                }
            }
        }
    }
    (w, distance)
}

#[test]
fn every_ascii_glyph_decomposes_to_its_winding_number_wherever_it_stands() {
    let text: String = (33u8..127).map(char::from).collect();
    let mut rng = Rng::new(7);
    let mut unit = move || rng.unit();
    for valign in [VAlign::Baseline, VAlign::Center] {
        let params = TextParams {
            text: &text,
            size: 7.0,
            spacing: 1.0,
            halign: HAlign::Left,
            valign,
            direction: None,
            language: None,
            script: None,
        };
        let glyphs = layout(SANS, 0, &params).unwrap();
        for glyph in &glyphs {
            let region = curved_cells(&glyph.contours, FillRule::NonZero).unwrap();
            let (lo, hi) = (region.min, region.max);
            for _ in 0..200 {
                let q = DVec2::new(lo.x + (hi.x - lo.x) * unit(), lo.y + (hi.y - lo.y) * unit());
                let (w, distance) = flattened_winding(&glyph.contours, q, 256);
                if distance < 1e-3 {
                    continue;
                }
                assert_eq!(
                    region.contains(q),
                    w != 0,
                    "glyph at byte {} ({valign:?}), {q}",
                    glyph.cluster
                );
            }
        }
    }
}
