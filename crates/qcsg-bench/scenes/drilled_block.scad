// A machined part: a block with four through holes, a counterbored centre hole and a chamfered
// edge (a half space cut at 45°).
difference() {
    cube([4, 3, 1], center = true);
    for (x = [-1.4, 1.4], y = [-0.9, 0.9])
        translate([x, y, 0]) cylinder(h = 2, r = 0.25, center = true);
    cylinder(h = 2, r = 0.5, center = true);
    translate([0, 0, 0.35]) cylinder(h = 1, r = 0.8);
    translate([2, 0, 0.5]) rotate([0, 45, 0]) cube([0.5, 4, 0.5], center = true);
}
