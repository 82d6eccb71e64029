// scale = 0: a disc swept to a point is a cone, an ellipse an elliptic cone.
$fn = 64;
linear_extrude(height = 8, scale = 0) circle(4);
translate([12, 0, 0]) linear_extrude(height = 5, scale = 0) scale([2, 1]) circle(2);
