// A rounded cross: the intersection of a ball with the union of three orthogonal cylinders,
// minus a smaller ball (curved feature curves everywhere, 5 quadrics).
difference() {
    intersection() {
        sphere(1.3);
        union() {
            cylinder(h = 3, r = 0.7, center = true);
            rotate([90, 0, 0]) cylinder(h = 3, r = 0.7, center = true);
            rotate([0, 90, 0]) cylinder(h = 3, r = 0.7, center = true);
        }
    }
    sphere(0.9);
}
