// for with two variables: every combination.
$fn = 32;
for (x = [0 : 2], y = [0 : 1]) translate([x * 4, y * 4, 0]) cube([2, 2, 1 + x + y]);
