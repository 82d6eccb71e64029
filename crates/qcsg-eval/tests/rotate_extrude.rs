//! `rotate_extrude`: each leaf of the 2-D shape read in (r, z) and swept about z (cones and
//! their outsides for slanted edges, spheres for discs on the axis), partial angles as wedges,
//! shapes at x ≤ 0 mirrored as OpenSCAD sweeps them, and the errors for tori and for shapes on
//! both sides of the axis.

mod common;

use common::{codes, eval, membership, p};

#[test]
fn slanted_edges_sweep_cones_and_their_outsides() {
    // Outer edge slanted (r ≤ 5 − 2z): inside a cone, only its lower nappe.
    membership(
        "rotate_extrude() polygon([[1, 0], [5, 0], [1, 2]]);",
        &[
            (p(0.0, 2.0, 0.5), true),
            (p(-2.9, 0.0, 0.9), true),
            (p(0.0, 3.3, 0.9), false),
            (p(0.5, 0.0, 0.5), false), // the hole r < 1
            (p(1.2, 0.0, 2.5), false), // the upper nappe is not in it
        ],
    );
    // Inner edge slanted (r ≥ 2 + z/2): outside a cone, and all of r ≥ 0 below its apex.
    membership(
        "rotate_extrude() polygon([[2, 0], [5, 0], [5, 2], [3, 2]]);",
        &[
            (p(0.0, 4.0, 1.0), true),
            (p(2.2, 0.0, 0.1), true),
            (p(2.2, 0.0, 1.5), false),
            (p(0.0, 0.0, 1.0), false),
            (p(5.5, 0.0, 1.0), false),
        ],
    );
}

#[test]
fn discs_on_the_axis_sweep_balls_and_shapes_at_negative_x_are_mirrored() {
    membership(
        "rotate_extrude() intersection() { translate([0, 3]) circle(2); square([5, 10]); }",
        &[
            (p(1.3, 1.3, 3.5), true),
            (p(0.0, 0.0, 4.9), true),
            (p(1.5, 1.5, 3.0), false),
            (p(0.0, 0.0, 5.1), false),
        ],
    );
    membership(
        "rotate_extrude() translate([-5, 0]) square([2, 3]);",
        &[
            (p(4.0, 0.0, 1.0), true),
            (p(0.0, -4.0, 1.0), true),
            (p(2.0, 0.0, 1.0), false),
            (p(0.0, 6.0, 1.0), false),
        ],
    );
}

#[test]
fn partial_angles_are_wedges() {
    // 90°: the first quadrant; −90°: the fourth; 270°: all but the fourth.
    let ring = "translate([2, 0]) square([2, 1])";
    let cases = |inside: [bool; 4]| {
        [
            (p(2.1, 2.1, 0.5), inside[0]),
            (p(-2.1, 2.1, 0.5), inside[1]),
            (p(-2.1, -2.1, 0.5), inside[2]),
            (p(2.1, -2.1, 0.5), inside[3]),
        ]
    };
    membership(
        &format!("rotate_extrude(angle = 90) {ring};"),
        &cases([true, false, false, false]),
    );
    membership(
        &format!("rotate_extrude(angle = -90) {ring};"),
        &cases([false, false, false, true]),
    );
    membership(
        &format!("rotate_extrude(angle = 270) {ring};"),
        &cases([true, true, true, false]),
    );
    membership(
        &format!("rotate_extrude(angle = 720) {ring};"),
        &cases([true, true, true, true]),
    );
    // A shape at x ≤ 0 starts from −x.
    membership(
        "rotate_extrude(angle = 90) translate([-4, 0]) square([2, 1]);",
        &cases([false, false, true, false]),
    );
    let found = codes(&eval(&format!(
        "rotate_extrude(angle = 0) {ring}; cube(1);"
    )));
    assert_eq!(found, ["W0553"]);
}

fn first_error(text: &str) -> qcsg_diag::Diagnostic {
    let e = eval(text);
    e.diagnostics
        .iter()
        .find(|d| d.is_error())
        .cloned()
        .unwrap_or_else(|| panic!("{text}: no error in {:?}", e.diagnostics))
}

fn at(text: &str, span: qcsg_diag::Span) -> &str {
    &text[span.start as usize..span.end as usize]
}

#[test]
fn a_circle_off_the_axis_is_a_torus_and_an_error_at_the_circle() {
    let text = "rotate_extrude($fn = 64) translate([5, 0]) circle(1);";
    let d = first_error(text);
    assert_eq!(d.code, "E0301");
    assert!(d.message.contains("torus"), "{}", d.message);
    assert!(
        at(text, d.span).starts_with("circle(1)"),
        "{}",
        at(text, d.span)
    );
    assert!(at(text, d.labels[0].span).starts_with("rotate_extrude"));
    assert!(d.help.is_some());
}

#[test]
fn a_shape_across_the_axis_is_an_error_at_the_call() {
    let text = "rotate_extrude() square(2, center = true);";
    let d = first_error(text);
    assert_eq!(d.code, "E0564");
    assert_eq!(at(text, d.span), text);
    assert!(d.message.contains("from -1 to 1"), "{}", d.message);
    let text = "rotate_extrude(angle = 1 / 0) square(2);";
    let d = first_error(text);
    assert_eq!(d.code, "E0552");
    assert_eq!(at(text, d.span), "angle = 1 / 0");
}
