// Cones and frusta: r1/r2, d1/d2, positional, centred.
$fn = 32;
cylinder(h = 10, r1 = 5, r2 = 2);
translate([12, 0, 0]) cylinder(h = 6, d1 = 2, d2 = 8, center = true);
translate([0, 12, 0]) cylinder(8, 3, 1);
