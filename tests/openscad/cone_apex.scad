// Cones closing to a point, upwards and downwards.
$fn = 32;
cylinder(h = 10, r1 = 4, r2 = 0);
translate([10, 0, 0]) cylinder(h = 6, r1 = 0, r2 = 3, center = true);
