// Work for the pruning passes: a plate with a grid of 25 holes, a third of them outside the
// plate, a ball inside another ball, a box beside the part that misses it in an intersection.
union() {
    difference() {
        cube([3, 3, 0.4], center = true);
        for (x = [-2 : 1 : 2], y = [-2 : 1 : 2])
            translate([0.9 * x, 0.9 * y, 0]) cylinder(h = 1, r = 0.2, center = true);
    }
    translate([0, 0, 1]) sphere(0.8);
    translate([0.2, 0, 1]) sphere(0.3);
    intersection() {
        translate([0, 0, 1]) sphere(0.5);
        translate([5, 5, 5]) cube(1);
    }
}
