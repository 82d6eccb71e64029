// difference: the first child minus the others.
$fn = 32;
difference() {
    cube(8, center = true);
    sphere(5);
    cylinder(h = 20, r = 2, center = true);
}
