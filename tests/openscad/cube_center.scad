// Centred cubes.
$fn = 32;
cube(5, center = true);
translate([8, 0, 0]) cube([2, 4, 6], center = true);
