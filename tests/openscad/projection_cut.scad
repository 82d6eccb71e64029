// projection(cut = true): the section of solids by z = 0, extruded. A ball, a tilted cylinder
// (an ellipse), a cone cut across (a disc), a box with a hole and a solid wholly above the plane
// (nothing), all exact.
$fn = 128;
linear_extrude(2) projection(cut = true) {
    translate([0, 0, 1]) sphere(3);
    translate([8, 0, 0]) rotate([40, 0, 0]) cylinder(h = 10, r = 1.5, center = true);
    translate([0, 8, -2]) cylinder(h = 6, r1 = 4, r2 = 1);
    translate([10, 8, 0]) difference() {
        cube([6, 4, 2], center = true);
        rotate([0, 30, 0]) cylinder(h = 10, r = 1, center = true);
    }
    translate([0, -8, 1]) cube(2);
}
