// hull of cylinders and cones with parallel axes at different heights (a tapered stand), and
// minkowski of a box with a cone (a plate with sloped, rounded sides).
$fn = 128;
hull() {
    cylinder(h = 1, r = 4);
    translate([0, 0, 1]) cylinder(h = 5, r1 = 3, r2 = 1.5);
    translate([6, 0, 0]) cylinder(h = 2, r1 = 1.5, r2 = 0.5);
}
translate([0, 12, 0]) rotate([0, 0, 20]) minkowski() {
    cube([6, 3, 1], center = true);
    cylinder(h = 1.5, r1 = 1, r2 = 0.25);
}
