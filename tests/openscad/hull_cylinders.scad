// hull of parallel cylinders of one radius and height: the rounded plate of four vertical
// cylinders, and three cylinders lying along x (turned), each their discs' hull extruded.
$fn = 128;
hull() for (x = [1, 9], y = [1, 5]) translate([x, y, 0]) cylinder(h = 2, r = 1);
translate([0, 10, 0]) rotate([0, 90, 0]) hull() {
    cylinder(h = 6, r = 0.8);
    translate([-3, 1, 0]) cylinder(h = 6, r = 0.8);
    translate([-1, 3, 0]) cylinder(h = 6, r = 0.8);
}
