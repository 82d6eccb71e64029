//! `projection`: the section by z = 0 (`cut = true`, exact leaf by leaf) and the shadow
//! (`cut = false`, exact where projection commutes with the booleans), and the error for shadows
//! it does not compute.

mod common;

use common::{eval, membership, p};

#[test]
fn the_section_is_each_quadric_restricted_to_the_ground() {
    // A ball of radius 5 centred at z = 3 meets z = 0 in a disc of radius 4; a cube above the
    // plane has no section.
    let found = membership(
        "linear_extrude(1) projection(cut = true) {
             translate([0, 0, 3]) sphere(5);
             translate([20, 0, 1]) cube(2);
         }",
        &[
            (p(3.9, 0.0, 0.5), true),
            (p(0.0, -3.9, 0.5), true),
            (p(4.1, 0.0, 0.5), false),
            (p(21.0, 1.0, 0.5), false),
        ],
    );
    assert!(found.is_empty(), "{found:?}");
    // A difference: the section of a box minus a ball is a square minus a disc.
    membership(
        "linear_extrude(1) projection(cut = true) difference() {
             cube(10, center = true); sphere(3);
         }",
        &[
            (p(4.0, 4.0, 0.5), true),
            (p(2.0, 2.0, 0.5), false),
            (p(5.5, 0.0, 0.5), false),
        ],
    );
}

#[test]
fn the_shadow_of_balls_boxes_and_vertical_cylinders() {
    membership(
        "linear_extrude(1) projection() {
             translate([0, 0, 7]) sphere(2);
             translate([10, 0, -4]) cylinder(h = 2, r = 1);
             translate([20, 0, 9]) rotate([0, 0, 90]) cube(4, center = true);
         }",
        &[
            (p(1.9, 0.0, 0.5), true),
            (p(10.9, 0.0, 0.5), true),
            (p(21.9, 1.9, 0.5), true),
            (p(2.1, 0.0, 0.5), false),
            (p(11.1, 0.0, 0.5), false),
            (p(22.1, 0.0, 0.5), false),
        ],
    );
}

#[test]
fn a_shadow_not_computed_exactly_is_an_error_at_the_call() {
    // A cone cut by a slab (cylinder with two radii): two parts that depend on z, intersected.
    let text = "linear_extrude(1) projection() cylinder(h = 3, r1 = 2, r2 = 1);";
    let e = eval(text);
    let d = e
        .diagnostics
        .iter()
        .find(|d| d.is_error())
        .unwrap_or_else(|| panic!("no error: {:?}", e.diagnostics));
    assert_eq!(d.code, "E0301");
    assert_eq!(
        &text[d.span.start as usize..d.span.end as usize],
        "projection() cylinder(h = 3, r1 = 2, r2 = 1);"
    );
    assert!(d.help.as_deref().is_some_and(|h| h.contains("cut = true")));
    let label = &d.labels[0];
    assert!(text[label.span.start as usize..label.span.end as usize].starts_with("cylinder"));
    // With cut = true the same part is fine.
    membership(
        "linear_extrude(1) projection(cut = true) translate([0, 0, -1]) cylinder(h = 3, r1 = 2, r2 = 1);",
        &[(p(1.6, 0.0, 0.5), true), (p(1.7, 0.0, 0.5), false)],
    );
}

#[test]
fn a_projection_is_a_2d_shape() {
    // At the top level it is a plate, and 2-D children are ignored as OpenSCAD does.
    let found = membership(
        "projection(cut = true) { sphere(2); square(10); }",
        &[(p(1.0, 1.0, 0.4), true), (p(5.0, 5.0, 0.0), false)],
    );
    assert!(found.contains(&"W0560"), "{found:?}");
    assert!(found.contains(&"W0559"), "{found:?}");
}
