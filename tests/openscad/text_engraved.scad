// A plate with a name engraved in it: the plate minus extruded text, regular and bold, with
// letters whose counters (the holes of "e", "a", "o", "g") stay standing as islands.
$fn = 128;
difference() {
    translate([-42, -14, 0]) cube([84, 28, 4]);
    translate([0, 3, 2]) linear_extrude(height = 3)
        text("Grace Hopper", size = 8, halign = "center", valign = "center");
    translate([0, -8, 3]) linear_extrude(height = 2)
        text("COBOL 1959", size = 5, font = "Liberation Sans:style=Bold", halign = "center");
}
