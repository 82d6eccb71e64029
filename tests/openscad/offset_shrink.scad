// offset shrinking: a square by r and by delta (its edges shifted inwards), a disc, and a
// square with a round end (an intersection of edges and a disc).
$fn = 128;
linear_extrude(1) offset(r = -1) square([6, 4]);
translate([10, 0, 0]) linear_extrude(1) offset(delta = -0.5) polygon([[0, 0], [5, 0], [6, 4], [1, 5]]);
translate([0, 10, 0]) linear_extrude(1) offset(-1) circle(3);
translate([10, 10, 0]) linear_extrude(1) offset(r = -0.5) intersection() { square(4); circle(4.5); }
