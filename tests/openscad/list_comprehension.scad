// list comprehensions: for, if, each, let, nested.
$fn = 32;
points = [for (i = [0 : 4]) if (i % 2 == 0) [i * 4, 0, 0]];
for (p = points) translate(p) cube(2);
rings = [for (i = [1 : 3]) let (r = i * 0.5) [i * 5, 8, r]];
for (c = rings) translate([c[0], c[1], 0]) sphere(c[2] + 1);
flat = [each [1, 2], for (j = [3 : 4]) j];
for (k = flat) translate([k * 3, -6, 0]) cube([1, 1, k]);
