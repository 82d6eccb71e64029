// intersection of a cube, a sphere and a rotated cylinder.
$fn = 32;
intersection() {
    cube(8, center = true);
    sphere(5.5);
    rotate([90, 0, 0]) cylinder(h = 20, r = 3.5, center = true);
}
