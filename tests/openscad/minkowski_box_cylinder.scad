// minkowski of a box with a vertical cylinder: the plate with rounded vertical edges, turned and
// moved, and of an L of two boxes (not convex) with a shorter, thinner cylinder.
$fn = 128;
translate([1, -2, 3]) rotate([15, -20, 35]) minkowski() {
    cube([6, 4, 2], center = true);
    cylinder(r = 1, h = 1);
}
translate([0, 12, 0]) minkowski() {
    union() { cube([6, 2, 1]); cube([2, 5, 1]); }
    translate([0, 0, -0.5]) cylinder(r = 0.6, h = 0.5);
}
