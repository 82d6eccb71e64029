// A labelled part: a mounting block whose name and size are raised on its top face in Liberation
// Sans Bold, and whose side carries a serif part number. Shows: text() with a font by name,
// halign and valign, on 2-D shapes extruded like any other; each glyph is exact, its straight
// edges planes and its curves parabolic cylinders (TrueType's quadratic arcs), so the letters'
// round parts are as smooth as the bore beside them.
// preview: --camera 45,-80,75,0,-3,4 --size 480,360

width = 70;
depth = 34;
height = 8;
bore = 6;

difference() {
    translate([-width / 2, -depth / 2, 0]) cube([width, depth, height]);
    for (x = [-width / 2 + 8, width / 2 - 8])
        translate([x, 0, -1]) cylinder(h = height + 2, d = bore);
}
// The name, centred on the top face.
translate([0, 4, height])
    linear_extrude(height = 1.5)
        text("QCSG", size = 10, font = "Liberation Sans:style=Bold",
            halign = "center", valign = "center");
// The size below it, smaller.
translate([0, -9, height])
    linear_extrude(height = 1)
        text("M6 x 70", size = 5, halign = "center", valign = "center");
// A part number on the front face, standing out of it.
translate([0, -depth / 2, height / 2])
    rotate([90, 0, 0])
        linear_extrude(height = 0.8)
            text("No. 40-A", size = 4, font = "Liberation Serif",
                halign = "center", valign = "center");
