//! Placement: each primitive and transform puts its solid where OpenSCAD does, checked by point
//! membership in the DAG, and right-angle rotations keep quadrics exactly axis-aligned.

mod common;

use common::{codes, eval, p};
use qcsg_csg::{Dag, Edge, NodeKind};
use qcsg_eval::codes as c;
use qcsg_quadric::{DMat4, DVec3};

/// Asserts membership of every point: `inside` in the solid, `outside` not.
fn check(text: &str, inside: &[DVec3], outside: &[DVec3]) {
    let e = eval(text);
    assert!(!e.has_errors(), "{text}: {:?}", e.diagnostics);
    for q in inside {
        assert!(e.dag.contains(*q), "{text}: {q} should be inside");
    }
    for q in outside {
        assert!(!e.dag.contains(*q), "{text}: {q} should be outside");
    }
}

#[test]
fn cube_spans_zero_to_size_unless_centred() {
    check(
        "cube(2);",
        &[p(1.0, 1.0, 1.0), p(0.0, 0.0, 0.0), p(2.0, 2.0, 2.0)],
        &[p(2.1, 1.0, 1.0), p(-0.1, 1.0, 1.0), p(1.0, 1.0, 2.1)],
    );
    check(
        "cube([1, 2, 3], center = true);",
        &[p(0.49, 0.99, 1.49), p(-0.49, -0.99, -1.49)],
        &[p(0.51, 0.0, 0.0), p(0.0, 1.01, 0.0), p(0.0, 0.0, 1.51)],
    );
    check(
        "cube(size = [1, 2, 3]);",
        &[p(0.5, 1.9, 2.9)],
        &[p(0.5, 2.1, 1.0)],
    );
}

#[test]
fn sphere_and_ellipsoid() {
    check(
        "sphere(2);",
        &[p(1.9, 0.0, 0.0), p(0.0, 0.0, -1.9)],
        &[p(1.5, 1.5, 0.0)],
    );
    check("sphere(d = 2);", &[p(0.99, 0.0, 0.0)], &[p(1.01, 0.0, 0.0)]);
    check("sphere();", &[p(0.99, 0.0, 0.0)], &[p(1.01, 0.0, 0.0)]);
    check(
        "ellipsoid(r = [3, 2, 1]);",
        &[p(2.9, 0.0, 0.0), p(0.0, 1.9, 0.0), p(0.0, 0.0, 0.9)],
        &[p(0.0, 0.0, 1.1), p(0.0, 2.1, 0.0)],
    );
}

#[test]
fn cylinders_and_cones_span_zero_to_h() {
    check(
        "cylinder(h = 2, r = 1);",
        &[p(0.9, 0.0, 1.9), p(0.0, 0.0, 0.0)],
        &[p(0.0, 0.0, 2.1), p(1.1, 0.0, 1.0), p(0.0, 0.0, -0.1)],
    );
    check(
        "cylinder(2, 1, 1, true);",
        &[p(0.0, 0.0, -0.9)],
        &[p(0.0, 0.0, 1.1)],
    );
    check(
        "cylinder(h = 2, d = 4);",
        &[p(1.9, 0.0, 1.0)],
        &[p(2.1, 0.0, 1.0)],
    );
    // A cone with its apex at the top.
    check(
        "cylinder(h = 2, r1 = 1, r2 = 0);",
        &[p(0.0, 0.0, 1.9), p(0.4, 0.0, 1.1), p(0.99, 0.0, 0.0)],
        &[p(0.5, 0.0, 1.1), p(0.0, 0.0, 2.1), p(0.0, 0.0, -0.1)],
    );
    // A frustum: radius 2 at the bottom, 1 at the top.
    check(
        "cylinder(h = 2, r1 = 2, r2 = 1);",
        &[p(1.9, 0.0, 0.0), p(0.9, 0.0, 2.0), p(1.4, 0.0, 1.0)],
        &[p(1.6, 0.0, 1.0), p(1.1, 0.0, 1.9), p(0.0, 0.0, 2.5)],
    );
    check(
        "cylinder(h = 4, d1 = 0, d2 = 4, center = true);",
        &[p(1.9, 0.0, 2.0)],
        &[p(0.1, 0.0, -1.9)],
    );
}

#[test]
fn quadric_native_primitives() {
    check(
        "paraboloid(h = 4, r = 2);",
        &[p(0.0, 0.0, 0.1), p(1.9, 0.0, 3.99), p(0.9, 0.0, 1.0)],
        &[p(0.0, 0.0, -0.1), p(0.0, 0.0, 4.1), p(1.1, 0.0, 1.0)],
    );
    check(
        "cone(h = 2, r = 1);",
        &[p(0.0, 0.0, 0.01), p(0.45, 0.0, 1.0), p(0.99, 0.0, 2.0)],
        &[p(0.55, 0.0, 1.0), p(0.0, 0.0, -1.0), p(0.0, 0.0, 2.1)],
    );
    check(
        "hyperboloid(h = 2, r = 1, c = 1, center = true);",
        &[p(0.99, 0.0, 0.0), p(1.4, 0.0, 1.0)],
        &[p(1.01, 0.0, 0.0), p(1.5, 0.0, 1.0), p(0.0, 0.0, 1.1)],
    );
    check(
        "hyperboloid(h = 6, r = 1, c = 1, sheets = 2, center = true);",
        &[p(0.0, 0.0, 1.1), p(0.0, 0.0, -2.9), p(1.0, 0.0, 2.9)],
        &[p(0.0, 0.0, 0.9), p(0.0, 0.0, 3.1)],
    );
    check(
        "intersection() { halfspace([0, 0, 1], 1); cube(4, center = true); }",
        &[p(0.0, 0.0, 0.9), p(0.0, 0.0, -1.9)],
        &[p(0.0, 0.0, 1.1)],
    );
    check(
        "intersection() { quadric([1, 1, 1, 0, 0, 0, 0, 0, 0, -4]); cube(10, center = true); }",
        &[p(1.9, 0.0, 0.0)],
        &[p(2.1, 0.0, 0.0)],
    );
    check(
        "intersection() { quadric([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 0], [0, 0, 0, -1]]); cube(4, center = true); }",
        &[p(0.9, 0.0, 1.9)],
        &[p(1.1, 0.0, 0.0)],
    );
    check(
        "intersection() { cube(4, center = true); complement() sphere(1); }",
        &[p(1.5, 0.0, 0.0)],
        &[p(0.0, 0.0, 0.0), p(2.5, 0.0, 0.0)],
    );
}

#[test]
fn transforms_place_children() {
    check(
        "translate([5, 0, 0]) cube(1);",
        &[p(5.5, 0.5, 0.5)],
        &[p(0.5, 0.5, 0.5)],
    );
    check(
        "translate([1, 2]) cube(1);",
        &[p(1.5, 2.5, 0.5)],
        &[p(1.5, 2.5, 1.5)],
    );
    check(
        "rotate(90) cube([2, 1, 1]);",
        &[p(-0.5, 1.5, 0.5)],
        &[p(1.5, 0.5, 0.5)],
    );
    check(
        "rotate([90, 0, 0]) cube([1, 2, 3]);",
        &[p(0.5, -2.5, 1.5)],
        &[p(0.5, 2.5, 1.5)],
    );
    check(
        "rotate([0, 90, 0]) cube([3, 1, 1]);",
        &[p(0.5, 0.5, -2.5)],
        &[p(2.5, 0.5, 0.5)],
    );
    check(
        "rotate(a = 90, v = [1, 0, 0]) cube([1, 2, 3]);",
        &[p(0.5, -2.5, 1.5)],
        &[],
    );
    check(
        "rotate(180, [0, 0, 0]) cube(1);",
        &[p(0.5, 0.5, 0.5)],
        &[p(-0.5, -0.5, 0.5)],
    );
    check(
        "rotate([90, 0, 90]) cube([3, 1, 1]);",
        &[p(0.0, 2.5, 0.5)],
        &[p(2.5, 0.5, 0.5)],
    );
    check(
        "scale([2, 1, 1]) sphere(1);",
        &[p(1.9, 0.0, 0.0)],
        &[p(0.0, 1.1, 0.0)],
    );
    check(
        "scale(3) cube(1);",
        &[p(2.9, 2.9, 2.9)],
        &[p(3.1, 1.0, 1.0)],
    );
    check(
        "mirror([1, 0, 0]) cube(1);",
        &[p(-0.5, 0.5, 0.5)],
        &[p(0.5, 0.5, 0.5)],
    );
    check("mirror([0, 0, 0]) cube(1);", &[p(0.5, 0.5, 0.5)], &[]);
    check(
        "multmatrix([[1, 0, 0, 10], [0, 1, 0, 20], [0, 0, 1, 30]]) cube(1);",
        &[p(10.5, 20.5, 30.5)],
        &[p(0.5, 0.5, 0.5)],
    );
    check(
        "resize([4, 4, 4]) sphere(1);",
        &[p(1.9, 0.0, 0.0)],
        &[p(2.1, 0.0, 0.0)],
    );
    check(
        "resize([4, 0, 0], auto = true) cube([2, 1, 1]);",
        &[p(3.9, 1.9, 1.9)],
        &[p(4.1, 1.0, 1.0)],
    );
    check(
        "resize([4, 0, 0]) cube([2, 1, 1]);",
        &[p(3.9, 0.9, 0.9)],
        &[p(1.0, 1.1, 0.5)],
    );
    check(
        "color(\"red\") color([0, 1, 0], 0.5) cube(1);",
        &[p(0.5, 0.5, 0.5)],
        &[],
    );
    check(
        "translate([10, 0, 0]) rotate(90) translate([1, 0, 0]) cube(1);",
        &[p(9.5, 1.5, 0.5)],
        &[p(10.5, 1.5, 0.5)],
    );
}

/// The world-space quadric coefficients of every leaf reachable from `edge`.
fn world_coefficients(dag: &Dag, edge: Edge, m: DMat4, out: &mut Vec<[f64; 10]>) {
    let m = m * dag.matrix(edge.transform);
    let Some(node) = dag.node(edge.child) else {
        return;
    };
    match &node.kind {
        NodeKind::Leaf(q) => out.push(q.transformed(&m).expect("invertible").coefficients()),
        kind => {
            for e in kind.children() {
                world_coefficients(dag, *e, m, out);
            }
        }
    }
}

#[test]
fn right_angle_rotations_keep_quadrics_axis_aligned() {
    for text in [
        "rotate(90) cube([2, 1, 1]);",
        "rotate([90, 180, 270]) cylinder(h = 2, r1 = 1, r2 = 2);",
        "rotate(a = -90, v = [0, 1, 0]) cube(1);",
        "rotate([0, 90, 0]) ellipsoid([1, 2, 3]);",
        "mirror([0, 1, 0]) rotate(270) cube(3);",
    ] {
        let e = eval(text);
        let root = e.dag.root().expect("root");
        let mut all = Vec::new();
        world_coefficients(&e.dag, root, DMat4::IDENTITY, &mut all);
        assert!(!all.is_empty());
        for k in all {
            assert_eq!(&k[3..6], &[0.0, 0.0, 0.0], "{text}: {k:?}");
        }
    }
}

#[test]
fn booleans_and_modifiers() {
    check(
        "difference() { cube(2); sphere(1); }",
        &[p(1.9, 1.9, 1.9)],
        &[p(0.1, 0.1, 0.1), p(3.0, 0.0, 0.0)],
    );
    check(
        "intersection() { cube(2); sphere(1); }",
        &[p(0.1, 0.1, 0.1)],
        &[p(1.9, 1.9, 1.9), p(-0.1, 0.0, 0.0)],
    );
    // An empty group (an `if` that is false) is no child at all, as in OpenSCAD.
    check(
        "intersection() { cube(2); if (false) sphere(1); }",
        &[p(1.9, 1.9, 1.9)],
        &[],
    );
    check(
        "intersection_for(i = [0, 1]) translate([i, 0, 0]) cube(2);",
        &[p(1.5, 1.0, 1.0)],
        &[p(0.5, 1.0, 1.0), p(2.5, 1.0, 1.0)],
    );
    check(
        "union() { cube(1); translate([5, 0, 0]) cube(1); }",
        &[p(5.5, 0.5, 0.5), p(0.5, 0.5, 0.5)],
        &[],
    );
    check(
        "cube(1); %translate([5, 0, 0]) cube(1); *translate([9, 0, 0]) cube(1);",
        &[p(0.5, 0.5, 0.5)],
        &[p(5.5, 0.5, 0.5), p(9.5, 0.5, 0.5)],
    );
    check(
        "translate([10, 0, 0]) !cube(1); sphere(5);",
        &[p(0.5, 0.5, 0.5)],
        &[p(3.0, 0.0, 0.0), p(10.5, 0.5, 0.5)],
    );
    check("#cube(1);", &[p(0.5, 0.5, 0.5)], &[]);
    let e = eval("*echo(\"never\"); %echo(\"background\");");
    assert_eq!(e.echo_lines(), ["ECHO: \"background\""]);
    let e = eval("cube(1); %sphere(1);");
    assert_eq!(e.dag.backgrounds().len(), 1);
}

#[test]
fn degenerate_input_is_empty_or_removed() {
    for text in [
        "cube(0);",
        "sphere(0);",
        "sphere(-1);",
        "cube([1, -1, 1]);",
        "cylinder(h = 0, r = 1);",
        "cylinder(h = 1, r = 0);",
    ] {
        let e = eval(text);
        assert!(!e.has_errors(), "{text}: {:?}", e.diagnostics);
        assert!(
            codes(&e).contains(&c::EMPTY_PRIMITIVE),
            "{text}: {:?}",
            e.diagnostics
        );
        assert!(!e.dag.contains(p(0.0, 0.0, 0.0)), "{text}");
    }
    let e = eval("scale(0) cube(1); scale([1, 0, 1]) sphere(1);");
    assert!(!e.has_errors());
    assert_eq!(codes(&e), [c::SINGULAR_TRANSFORM, c::SINGULAR_TRANSFORM]);
    assert!(!e.dag.contains(p(0.5, 0.0, 0.5)));
    let e = eval("");
    assert!(!e.has_errors());
    assert!(!e.dag.contains(p(0.0, 0.0, 0.0)));
}

#[test]
fn repeated_instances_share_nodes() {
    let e = eval("module m() sphere(1);\nfor (i = [0 : 9]) translate([3 * i, 0, 0]) m();\n");
    let leaves = e
        .dag
        .nodes()
        .iter()
        .filter(|n| matches!(n.kind, NodeKind::Leaf(_)))
        .count();
    assert_eq!(leaves, 1);
    assert!(e.dag.contains(p(27.0, 0.0, 0.5)));
    let e = eval(
        "module w(r) cylinder(h = 1, r = r);\nfor (i = [0 : 4]) translate([5 * i, 0, 0]) w(1);\nw(2);\n",
    );
    let leaves = e
        .dag
        .nodes()
        .iter()
        .filter(|n| matches!(n.kind, NodeKind::Leaf(_)))
        .count();
    assert_eq!(leaves, 3, "two cylinders (r = 1, r = 2) share the slab");
}

#[test]
fn leaves_carry_their_source_spans() {
    let text = "translate([1, 0, 0])\n  sphere(2);\n";
    let e = eval(text);
    let leaf = e
        .dag
        .nodes()
        .iter()
        .find(|n| matches!(n.kind, NodeKind::Leaf(_)))
        .expect("leaf");
    assert_eq!(&text[leaf.source.span.range()], "sphere(2);");
}
