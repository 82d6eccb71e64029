// OpenSCAD constructs that no quadric represents exactly are errors with a reason and, where
// there is one, an alternative.

// (`hull` is evaluated exactly for convex polytopes and balls of any radii; its refusals are
// runtime errors, tested in qcsg-eval.)
// (`minkowski` is evaluated exactly for unions of convex polytopes and balls; its refusals are
// runtime errors too. `surface` builds OpenSCAD's mesh of its height map: its failures are runtime
// errors, tested in qcsg-eval.)
// (`text` is built exactly from TrueType fonts, whose outlines are lines and parabolic arcs: its
// refusals, a font with cubic outlines, are runtime errors, tested in qcsg-eval.)
translate([0, 0, 0]) text("hello");

// A user definition of the same name is fine: it shadows the OpenSCAD built-in (here only in
// the module's scope, since definitions are hoisted to the whole scope they are in).
module custom() {
    module circle(r) cylinder(h = 1, r = r);
    circle(3);
}
custom();
