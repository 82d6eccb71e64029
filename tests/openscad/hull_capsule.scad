// hull of two and three balls of one radius: capsules (one along a diagonal, as the arm of
// OpenSCAD's animation example) and a rounded triangle.
$fn = 128;
hull() { sphere(2); translate([10, 0, 0]) sphere(2); }
translate([0, 8, 0]) rotate([0, -30, 45]) hull() { sphere(1.5); translate([8, 0, 0]) sphere(1.5); }
translate([0, -10, 0]) hull() {
    sphere(1);
    translate([8, 0, 1]) sphere(1);
    translate([3, 5, 2]) sphere(1);
}
