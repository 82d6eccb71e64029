// children are evaluated in the caller's scope, under the module's transforms.
$fn = 32;
module around(n, r) for (i = [0 : n - 1]) rotate(i * 360 / n) translate([r, 0, 0]) children();
size = 2;
around(5, 8) cube(size, center = true);
around(3, 3) rotate([0, 90, 0]) cylinder(h = 2, r = 0.8, center = true);
