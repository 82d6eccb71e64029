// rotate(a): about z.
$fn = 32;
rotate(30) cube([8, 2, 3]);
rotate(-100) translate([3, 0, 0]) cube([4, 1, 1]);
