// hull of balls of different radii: a tapered capsule (two balls), the same on a slant, a hull
// of three balls, and a cube with a ball (a point is a ball of radius 0).
$fn = 128;
hull() { sphere(3); translate([12, 0, 0]) sphere(1); }
translate([0, 10, 0]) rotate([20, -30, 45]) hull() { sphere(1); translate([9, 0, 0]) sphere(2.5); }
translate([0, -12, 0]) hull() {
    sphere(1);
    translate([9, 0, 1]) sphere(2);
    translate([3, 6, 2]) sphere(3);
}
translate([18, 0, 0]) hull() { cube(4, center = true); translate([0, 0, 7]) sphere(1.5); }
