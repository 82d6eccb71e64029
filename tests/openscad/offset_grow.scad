// offset growing: rounded (r) and mitred (delta) squares, a chamfered square, a non-convex
// polygon grown by r (its convex cells grown and united), and a disc; all extruded.
$fn = 128;
linear_extrude(1) offset(r = 1) square([4, 3]);
translate([8, 0, 0]) linear_extrude(1) offset(delta = 1) square([4, 3]);
translate([16, 0, 0]) linear_extrude(1) offset(delta = 1, chamfer = true) square([4, 3]);
translate([0, 8, 0]) linear_extrude(1) offset(r = 0.75) polygon([[0, 0], [6, 0], [6, 5], [4, 5], [4, 2], [0, 2]]);
translate([10, 8, 0]) linear_extrude(1) offset(1.5) circle(2);
translate([16, 8, 0]) linear_extrude(1) offset(delta = 0.5) polygon([[0, 0], [4, 0], [5, 3], [1, 4]]);
