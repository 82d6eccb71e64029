// Without $fn OpenSCAD takes the fragment count from $fa and $fs: here 60 for r = 5.
// fragments: 40
$fa = 6;
$fs = 0.5;
sphere(5);
translate([12, 0, 0]) cylinder(h = 4, r = 4);
