// minkowski of a box with a ball: the box with rounded edges and corners, turned and moved (one
// object: OpenSCAD's unions of such meshes take minutes; unions are tested against distances).
$fn = 128;
translate([2, -1, 3]) rotate([10, 20, 30]) minkowski() { cube([6, 4, 2], center = true); sphere(1); }
