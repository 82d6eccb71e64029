// resize to absolute sizes, with auto and with zeros.
$fn = 32;
resize([10, 4, 6]) sphere(3);
translate([15, 0, 0]) resize([6, 0, 0], auto = true) cube([2, 3, 4]);
translate([0, 10, 0]) resize(newsize = [4, 4, 0]) cylinder(h = 3, r = 1);
