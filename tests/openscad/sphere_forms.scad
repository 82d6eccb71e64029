// Spheres by radius, by diameter, positional and named.
$fn = 32;
sphere(5);
translate([12, 0, 0]) sphere(d = 6);
translate([0, 12, 0]) sphere(r = 2.5);
