// if / else and the conditional operator.
$fn = 32;
big = true;
if (big) cube(6); else sphere(1);
if (!big) cube(1); else translate([10, 0, 0]) sphere(3);
translate([0, 10, 0]) cylinder(h = big ? 4 : 1, r = len("ab"));
