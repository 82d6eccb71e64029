// $fn set per call refines the mesh of one primitive.
$fn = 24;
sphere(4, $fn = 48);
translate([10, 0, 0]) cylinder(h = 5, r = 3, $fn = 64);
translate([0, 10, 0]) sphere(3);
