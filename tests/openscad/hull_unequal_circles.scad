// 2-D hull of circles of different radii with a square and a point-like triangle, and the hull
// of four vertical cylinders of different radii (a plate with unequal rounded corners).
$fn = 128;
linear_extrude(2) hull() {
    circle(2);
    translate([9, 1]) circle(0.75);
    translate([3, 6]) square([2, 1]);
    translate([-1, 3]) circle(1.25);
}
translate([14, 0, 0]) hull() {
    cylinder(h = 3, r = 2);
    translate([8, 0, 0]) cylinder(h = 3, r = 1);
    translate([8, 5, 0]) cylinder(h = 3, r = 0.5);
    translate([0, 6, 0]) cylinder(h = 3, r = 1.5);
}
