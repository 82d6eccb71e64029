// Vertical text: top to bottom and bottom to top, with each horizontal and vertical alignment,
// glyphs of different heights and widths (FreeType's made-up vertical metrics).
$fn = 128;
linear_extrude(height = 2) {
    text("Wig", size = 6, direction = "ttb");
    translate([12, 0]) text("Lq7", size = 6, direction = "btt");
    translate([24, 0]) text("fAy", size = 5, direction = "ttb", halign = "center", valign = "center");
    translate([36, 0]) text("Tj", size = 5, direction = "btt", halign = "right", valign = "top");
    translate([48, 0]) text("kP", size = 5, direction = "ttb", halign = "left", valign = "bottom",
                            spacing = 1.3);
    translate([60, 0]) text("Bold", size = 4, font = "Liberation Serif:style=Bold",
                            direction = "ttb", valign = "top");
}
