// scale by a vector and by a number.
$fn = 32;
scale([2, 1, 0.5]) sphere(4);
translate([15, 0, 0]) scale(1.5) cube(3);
translate([0, 10, 0]) scale(v = [1, 3, 1]) cylinder(h = 2, r = 1);
