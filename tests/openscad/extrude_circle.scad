// Exact discs extruded, and a disc with a square hole.
$fn = 64;
linear_extrude(height = 6, center = true) circle(r = 3);
translate([8, 0, 0]) linear_extrude(4) circle(d = 5);
translate([0, 9, 0]) linear_extrude(3) difference() {
    circle(4);
    square(3, center = true);
}
