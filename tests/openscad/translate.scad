// translate with positional and named vectors, and a 2-vector.
$fn = 32;
translate([5, -3, 2]) cube(3);
translate(v = [-6, 0, 0]) sphere(2);
translate([0, 6]) cylinder(h = 2, r = 1.5);
