// cube at the corner: size as a vector and as a number.
$fn = 32;
cube([4, 6, 8]);
translate([6, 0, 0]) cube(3);
translate([0, 8, 0]) cube(size = [2, 3, 1], center = false);
