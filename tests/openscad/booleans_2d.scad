// 2-D unions, intersections and differences, extruded at once.
$fn = 64;
linear_extrude(height = 4) {
    intersection() {
        circle(5);
        square(6);
    }
    translate([12, 0]) union() {
        square([6, 2], center = true);
        square([2, 6], center = true);
    }
    translate([0, 12]) difference() {
        square(8, center = true);
        circle(3);
        translate([4, 4]) circle(2);
    }
}
