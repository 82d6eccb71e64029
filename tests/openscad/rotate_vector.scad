// rotate([x, y, z]): about x, then y, then z.
$fn = 32;
rotate([30, 45, 60]) cube([8, 3, 2], center = true);
translate([12, 0, 0]) rotate(a = [90, 0, 0]) cylinder(h = 6, r = 2);
