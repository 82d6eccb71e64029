// for over ranges, with and without a step.
$fn = 32;
for (i = [0 : 3]) translate([i * 5, 0, 0]) cylinder(h = i + 2, r = 1.5);
for (y = [2 : 3 : 9]) translate([0, y + 4, 0]) cube([2, 1, 1]);
