// projection(cut = false): the shadow of boxes, balls, an ellipsoid, a vertical cylinder and an
// extruded ring, extruded again.
$fn = 128;
linear_extrude(1) projection() {
    translate([0, 0, 5]) sphere(3);
    translate([6, -2, -3]) cube([4, 4, 9]);
    translate([0, 8, 2]) rotate([30, 20, 0]) scale([3, 1.5, 1]) sphere(1);
    translate([10, 8, -1]) linear_extrude(3) difference() { circle(3); circle(1); }
    translate([-8, 0, 0]) cylinder(h = 4, r = 2);
}
