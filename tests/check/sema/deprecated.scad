// OpenSCAD's deprecated child() and assign(): accepted with OpenSCAD's meaning, with a warning.

module first() child(0);
//             ^^^^^ warning[W0109]: `child` is deprecated
first() cube(1);

a = 10;
    assign(a = 1, b = a + 1) cube([a, b, 1]);
//  ^^^^^^ warning[W0109]: `assign` is deprecated

// The bindings are visible in the child only, as `let`'s are.
    assign(w = 2) {
//  ^^^^^^ warning[W0109]
    translate([w, 0, 0]) cube(w);
}
echo(w);
//   ^ error[E0101]: undefined variable

// Each value is resolved in the enclosing scope: `b2` is not yet bound for `c`.
    assign(b2 = 1, c = b2 + 1) echo(c);
//  ^^^^^^ warning[W0109]
//         ^^ warning[W0101]: `b2`
//                     ^^ error[E0101]

    assign(unused = 3, $fn = 8) sphere(1);
//  ^^^^^^ warning[W0109]
//         ^^^^^^ warning[W0101]
//                     ^^^ hint[H0101]

// A module of the program named like a deprecated one is that module.
module assign2() children();
assign2() cube(1);
module own() {
    module child() children();
    child() cube(1);
}
own();

// import_stl, import_off and import_dxf are import under old names; dxf_linear_extrude and
// dxf_rotate_extrude extrude an import; group is union, without a warning.
    import_stl("part.stl", convexity = 3);
//  ^^^^^^^^^^ warning[W0109]: `import_stl` is deprecated
    import_off(file = "part.off");
//  ^^^^^^^^^^ warning[W0109]: `import_off` is deprecated
    import_dxf("drawing.dxf", "layer", origin = [1, 2], scale = 2);
//  ^^^^^^^^^^ warning[W0109]: `import_dxf` is deprecated
    dxf_linear_extrude(file = "drawing.dxf", layer = "0", height = 2, twist = 0);
//  ^^^^^^^^^^^^^^^^^^ warning[W0109]: `dxf_linear_extrude` is deprecated
    dxf_rotate_extrude("drawing.dxf", "0", [0, 0], 1, angle = 90);
//  ^^^^^^^^^^^^^^^^^^ warning[W0109]: `dxf_rotate_extrude` is deprecated
group() { cube(1); sphere(1); }

// The extrusions' own `file` argument reads the drawing in place of the children.
linear_extrude(height = 2, file = "drawing.dxf", layer = "0");
//                         ^^^^^^^^^^^^^^^^^^^^ warning[W0109]: `linear_extrude(file = …)` is deprecated
rotate_extrude(file = "drawing.dxf", origin = [-5, 0]);
//             ^^^^^^^^^^^^^^^^^^^^ warning[W0109]: `rotate_extrude(file = …)` is deprecated
