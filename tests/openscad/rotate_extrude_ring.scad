// A ring: a rectangle off the axis sweeps a cylinder shell; a trapezoid off the axis sweeps a
// shell between a cylinder and a cone, and a half-disc on the axis a ball.
$fn = 128;
rotate_extrude() translate([5, 0]) square([2, 3]);
translate([0, 0, 5]) rotate_extrude() polygon([[3, 0], [6, 0], [4, 3], [3, 3]]);
translate([0, 0, 12]) rotate_extrude() intersection() { circle(3); translate([0, -3]) square([3, 6]); }
