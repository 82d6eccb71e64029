// A wheel: a disc with a hub bore, six bolt holes made in a loop, and a ball-shaped hub.
union() {
    difference() {
        cylinder(h = 0.6, r = 3, center = true);
        cylinder(h = 2, r = 2.4, center = true);
    }
    difference() {
        intersection() {
            cylinder(h = 0.6, r = 2.45, center = true);
            sphere(2.6);
        }
        for (i = [0 : 5])
            rotate([0, 0, 60 * i]) translate([1.5, 0, 0]) cylinder(h = 2, r = 0.3, center = true);
        cylinder(h = 2, r = 0.6, center = true);
    }
    for (i = [0 : 2])
        rotate([0, 0, 60 * i + 30]) cube([5, 0.3, 0.4], center = true);
}
