// A paragraph of 200 characters in Liberation Sans, five lines of 40, extruded 1 unit: many
// small glyph terms (about 70 a glyph), most of them far from any one ray or sample.
lines = [
    "Quadric solids keep every curve exact: a",
    "TrueType glyph is lines and parabolic ar",
    "cs, so text in Liberation Sans stays smo",
    "oth at any zoom, and far glyphs are prun",
    "ed from each query by their boxes. Done."
];
for (i = [0 : 4])
    translate([0, -12 * i, 0]) linear_extrude(height = 1) text(lines[i], size = 8);
