// booleans nested in booleans, with transforms between.
$fn = 32;
difference() {
    union() {
        cube([10, 10, 4]);
        translate([5, 5, 4]) cylinder(h = 4, r = 3);
    }
    translate([5, 5, -1]) cylinder(h = 12, r = 1.5);
    intersection() {
        translate([0, 0, 2]) cube([4, 4, 4]);
        translate([2, 2, 2]) sphere(2.5);
    }
}
