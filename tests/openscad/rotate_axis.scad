// rotate(a, v): about an arbitrary axis.
$fn = 32;
rotate(a = 40, v = [1, 1, 0]) cube([8, 3, 2]);
translate([12, 0, 0]) rotate(70, [0, 1, 1]) cylinder(h = 7, r1 = 2, r2 = 1);
