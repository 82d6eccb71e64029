// 2-D hull of squares and a polygon, and of circles of one radius (a rounded triangle and a
// stadium), extruded.
$fn = 128;
linear_extrude(2) hull() {
    square(2);
    translate([6, 0]) square([1, 3]);
    polygon([[3, 5], [4, 7], [2, 6]]);
}
translate([12, 0, 0]) linear_extrude(1) hull() {
    circle(1);
    translate([6, 0]) circle(1);
    translate([2, 4]) circle(1);
}
translate([0, 10, 0]) linear_extrude(1) hull() { circle(1.5); translate([7, 2]) circle(1.5); }
