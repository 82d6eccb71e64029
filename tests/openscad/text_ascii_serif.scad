// Every printable ASCII character in Liberation Serif, extruded: glyph outlines (lines and parabolic
// arcs), kerning and advances against OpenSCAD's flattened glyphs.
$fn = 128;
linear_extrude(height = 2) {
    translate([0, 0]) text(" !\"#$%&'()*+,-./0123456789:;<=>?", size = 8, font = "Liberation Serif");
    translate([0, -14]) text("@ABCDEFGHIJKLMNOPQRSTUVWXYZ[\\]^_", size = 8, font = "Liberation Serif");
    translate([0, -28]) text("`abcdefghijklmnopqrstuvwxyz{|}~", size = 8, font = "Liberation Serif");
}
