//! `offset`: growing unions of convex polygons and discs (rounded, mitred, chamfered corners),
//! shrinking intersections of edges and discs, and the error for what has no exact offset here.

mod common;

use common::{eval, membership};
use glam::DVec3;

fn p(x: f64, y: f64) -> DVec3 {
    DVec3::new(x, y, 0.5)
}

#[test]
fn corners_are_rounded_mitred_or_chamfered() {
    // Near the corner (0, 0) of a 4 × 4 square grown by 1.
    let corner = [p(-0.6, -0.6), p(-0.8, -0.8), p(-0.95, -0.95)];
    let cases = |inside: [bool; 3]| -> Vec<(DVec3, bool)> {
        corner
            .iter()
            .zip(inside)
            .map(|(c, i)| (*c, i))
            .chain([
                (p(-0.9, 2.0), true),
                (p(-1.1, 2.0), false),
                (p(2.0, 2.0), true),
            ])
            .collect()
    };
    // Rounded: within 1 of the corner (0.6·√2 ≈ 0.85 < 1 < 0.8·√2 ≈ 1.13).
    membership(
        "linear_extrude(1) offset(r = 1) square(4);",
        &cases([true, false, false]),
    );
    // Mitred: the whole square [−1, 5]².
    membership(
        "linear_extrude(1) offset(delta = 1) square(4);",
        &cases([true, true, true]),
    );
    // Chamfered: cut at distance 1 from the corner across the diagonal (x + y ≥ −√2).
    membership(
        "linear_extrude(1) offset(delta = 1, chamfer = true) square(4);",
        &cases([true, false, false]),
    );
    membership(
        "linear_extrude(1) offset(delta = 1, chamfer = true) square(4);",
        &[(p(-0.7, -0.7), true), (p(-0.72, -0.72), false)],
    );
}

#[test]
fn growing_a_non_convex_polygon_rounds_its_convex_corners_only() {
    // An L: the reflex corner at (2, 2) stays sharp when grown.
    let text = "linear_extrude(1) offset(r = 0.5) polygon([[0, 0], [6, 0], [6, 2], [2, 2], [2, 6], [0, 6]]);";
    membership(
        text,
        &[
            (p(2.45, 2.45), true),
            (p(2.55, 2.55), false),
            (p(6.3, 2.3), true),
            (p(6.45, 2.45), false),
            (p(1.0, 1.0), true),
        ],
    );
}

#[test]
fn shrinking_moves_edges_in_and_shrinks_discs() {
    membership(
        "linear_extrude(1) offset(r = -1) intersection() { square(6); circle(7); }",
        &[
            (p(1.1, 1.1), true),
            (p(0.9, 3.0), false),
            (p(4.9, 3.0), true),
            (p(5.1, 1.5), false),
            // The disc of radius 7 shrinks to 6: (4.9, 3.9) is at 6.26 from the origin.
            (p(4.9, 3.9), false),
        ],
    );
    let found = membership(
        "linear_extrude(1) offset(-3) circle(2); cube(1);",
        &[(p(0.5, 0.5), true), (p(-0.2, -0.2), false)],
    );
    assert!(found.is_empty(), "{found:?}");
}

#[test]
fn what_has_no_exact_offset_here_is_an_error_at_the_call() {
    let cases = [
        (
            "linear_extrude(1) offset(r = 1) difference() { square(4); square(2); }",
            "difference",
        ),
        (
            "linear_extrude(1) offset(r = 1) scale([2, 1]) circle(1);",
            "ellipse",
        ),
        (
            "linear_extrude(1) offset(r = -1) union() { square(4); translate([4, 0]) square(4); }",
            "union",
        ),
    ];
    for (text, what) in cases {
        let e = eval(text);
        let d = e
            .diagnostics
            .iter()
            .find(|d| d.is_error())
            .unwrap_or_else(|| panic!("{text}: no error"));
        assert_eq!(d.code, "E0301", "{text}");
        assert!(d.message.contains(what), "{text}: {}", d.message);
        assert!(
            text[d.span.start as usize..d.span.end as usize].starts_with("offset("),
            "{text}"
        );
        assert_eq!(d.labels.len(), 1, "{text}");
        assert!(d.help.is_some());
    }
}
