//! 2-D shapes as z-invariant solids: primitives, booleans and transforms in the plane, the
//! mixing rules of OpenSCAD 2021.01, the top-level plate, and `linear_extrude`.

mod common;

use common::{codes, eval, membership, p};

#[test]
fn a_top_level_shape_is_a_plate_with_a_warning() {
    let found = membership(
        "square([4, 2]);",
        &[
            (p(3.0, 1.0, 0.4), true),
            (p(3.0, 1.0, -0.4), true),
            (p(3.0, 1.0, 0.6), false),
            (p(5.0, 1.0, 0.0), false),
        ],
    );
    assert_eq!(found, ["W0560"]);
    let found = membership(
        "circle(d = 4, $fn = 5);",
        &[(p(1.9, 0.0, 0.0), true), (p(1.5, 1.5, 0.0), false)],
    );
    assert!(found.contains(&"W0560"), "{found:?}");
}

#[test]
fn transforms_act_in_the_plane() {
    // rotate([30, 0, 0]) keeps the xy part of the matrix: y shrinks by cos 30°, as in OpenSCAD.
    membership(
        "linear_extrude(5) rotate([30, 0, 0]) square(2);",
        &[
            (p(1.0, 1.7, 4.9), true),
            (p(1.0, 1.8, 1.0), false),
            (p(1.0, 1.0, 5.1), false),
        ],
    );
    // A 2-D translation's z is dropped, so is multmatrix's.
    membership(
        "linear_extrude(5) multmatrix([[1, 0, 0, 1], [0, 1, 0, 0], [0, 0, 1, 7], [0, 0, 0, 1]]) square(2);",
        &[(p(2.5, 1.0, 1.0), true), (p(0.5, 1.0, 1.0), false)],
    );
    membership(
        "linear_extrude(1) resize([4, 0], auto = true) square([1, 2]);",
        &[(p(3.9, 7.9, 0.5), true), (p(4.1, 1.0, 0.5), false)],
    );
    membership(
        "linear_extrude(1) mirror([1, 0]) translate([1, 0]) circle(0.5);",
        &[(p(-1.0, 0.0, 0.5), true), (p(1.0, 0.0, 0.5), false)],
    );
    // A singular 2-D transform removes the shape, as in OpenSCAD.
    let e = eval("linear_extrude(5) rotate([90, 0, 0]) square(2); cube(1);");
    assert!(codes(&e).contains(&"W0550"), "{:?}", codes(&e));
}

#[test]
fn booleans_of_shapes() {
    membership(
        "linear_extrude(2) difference() { square(10, center = true); circle(3); }",
        &[
            (p(4.0, 4.0, 1.0), true),
            (p(0.0, 0.0, 1.0), false),
            (p(4.0, 0.0, 3.0), false),
        ],
    );
    membership(
        "linear_extrude(2) intersection() { square(10, center = true); translate([5, 0]) circle(3); }",
        &[(p(4.0, 0.0, 1.0), true), (p(6.0, 0.0, 1.0), false)],
    );
}

#[test]
fn the_first_object_decides_the_dimension() {
    // A 3-D first child: the 2-D one is ignored, with a warning at it.
    let found = membership(
        "union() { cube(2); square(5); }",
        &[(p(1.0, 1.0, 1.0), true), (p(4.0, 4.0, 0.0), false)],
    );
    assert_eq!(found, ["W0559"]);
    // A 2-D first child: the cube is ignored and the result is a plate.
    let e = eval("union() { square(5); cube(2); }");
    let mut found = codes(&e);
    found.sort_unstable();
    assert_eq!(found, ["W0559", "W0560"]);
    assert!(e.dag.contains(p(4.0, 4.0, 0.0)) && !e.dag.contains(p(1.0, 1.0, 1.5)));
    // The same at the top level and in linear_extrude.
    let e = eval("cube(2); translate([3, 0, 0]) square(1);");
    assert_eq!(codes(&e), ["W0559"]);
    let e = eval("linear_extrude(3) { square(2); cube(3); }");
    assert_eq!(codes(&e), ["W0559"]);
    assert!(!e.dag.contains(p(2.5, 2.5, 1.0)));
    // Empty children do not count.
    let e = eval("union() { square(0); cube(2); }");
    assert_eq!(codes(&e), ["W0553"]);
}

#[test]
fn scaled_extrusions_are_cones_and_frusta() {
    // A circle to a point: a cone of radius 2 at z = 0 and apex at z = 4.
    membership(
        "linear_extrude(height = 4, scale = 0) circle(2);",
        &[
            (p(0.9, 0.0, 2.0), true),
            (p(1.1, 0.0, 2.0), false),
            (p(0.0, 0.0, 3.9), true),
            (p(0.0, 0.0, 4.1), false),
            (p(1.9, 0.0, 0.05), true),
        ],
    );
    // A centred frustum of a square, from side 4 at the bottom to side 2 at the top.
    membership(
        "linear_extrude(4, center = true, scale = 0.5) square(4, center = true);",
        &[
            (p(1.4, 1.4, 0.0), true),
            (p(1.6, 1.6, 0.0), false),
            (p(1.9, -1.9, -1.9), true),
            (p(1.1, 0.0, 1.9), false),
            (p(0.0, 0.0, 2.1), false),
        ],
    );
    // An off-centre square grows away from the axis: its sections scale about the z axis.
    membership(
        "linear_extrude(10, scale = 2) translate([2, 0]) square(1);",
        &[
            (p(2.5, 0.5, 0.5), true),
            (p(5.5, 1.5, 9.5), true),
            (p(2.5, 0.5, 9.5), false),
        ],
    );
    // Different scales in x and y are exact for straight edges, a turned square included.
    membership(
        "linear_extrude(2, scale = [2, 0.5]) rotate(45) square(1, center = true);",
        &[
            (p(0.0, 0.0, 1.0), true),
            (p(1.3, 0.0, 1.9), true),
            (p(0.0, 0.5, 1.9), false),
            (p(0.0, 0.6, 0.1), true),
        ],
    );
    // A polygon-free difference with a hole, scaled evenly: the hole becomes a cone.
    membership(
        "linear_extrude(3, scale = 1.5) difference() { square(6, center = true); circle(1); }",
        &[
            (p(1.2, 0.0, 0.1), true),
            (p(1.2, 0.0, 2.9), false),
            (p(4.3, 4.3, 2.9), true),
        ],
    );
}

#[test]
fn what_no_quadric_sweeps_is_an_error_at_its_argument() {
    let text = "linear_extrude(height = 3, twist = 90) square(2);";
    let e = eval(text);
    let d = e
        .diagnostics
        .iter()
        .find(|d| d.is_error())
        .expect("an error");
    assert_eq!(d.code, "E0301");
    assert_eq!(
        &text[d.span.start as usize..d.span.end as usize],
        "twist = 90"
    );
    assert!(d.help.is_some());
    let text = "linear_extrude(3, scale = [1, 2]) union() { square(1); circle(1); }";
    let e = eval(text);
    let d = e
        .diagnostics
        .iter()
        .find(|d| d.is_error())
        .expect("an error");
    assert_eq!(d.code, "E0301");
    assert_eq!(
        &text[d.span.start as usize..d.span.end as usize],
        "scale = [1, 2]"
    );
    let label = &d.labels[0];
    assert_eq!(
        &text[label.span.start as usize..label.span.end as usize],
        "circle(1);"
    );
    // Zero height: empty, with a warning, as in OpenSCAD.
    let e = eval("linear_extrude(0) square(1); cube(1);");
    assert_eq!(codes(&e), ["W0553"]);
}
