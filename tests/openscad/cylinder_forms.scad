// Cylinders: on the floor and centred, by radius and diameter.
$fn = 32;
cylinder(h = 10, r = 3);
translate([10, 0, 0]) cylinder(h = 8, d = 5, center = true);
translate([0, 10, 0]) cylinder(6, 2, 2);
