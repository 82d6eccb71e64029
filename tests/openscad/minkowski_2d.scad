// 2-D minkowski before linear_extrude: an L (not convex) rounded by a circle, and a triangle
// summed with a square and a circle.
$fn = 128;
linear_extrude(1.5) minkowski() {
    union() { square([6, 2]); square([2, 5]); }
    circle(0.75);
}
translate([10, 0, 0]) linear_extrude(1) minkowski() {
    polygon([[0, 0], [4, 0], [1, 3]]);
    square(1, center = true);
    circle(0.5);
}
