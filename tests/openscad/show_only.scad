// ! makes its subtree (without the transforms above it) the whole solid.
$fn = 32;
cube(10);
translate([20, 0, 0]) !rotate(30) cube([3, 4, 5]);
