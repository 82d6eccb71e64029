// A name plate: a rounded plate with raised bold text, centred, and a raised italic line below.
$fn = 128;
linear_extrude(height = 2) offset(r = 2) square([76, 26], center = true);
translate([0, 3, 0]) linear_extrude(height = 4)
    text("Ada Lovelace", size = 8, font = "Liberation Sans:style=Bold",
         halign = "center", valign = "center");
translate([0, -8, 0]) linear_extrude(height = 3)
    text("Analytical Engine", size = 4, font = "Liberation Serif:style=Italic",
         halign = "center");
