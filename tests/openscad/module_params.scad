// module parameters: defaults, named, positional, defaults that use other parameters.
$fn = 32;
module post(h = 5, r = 1, top = true) {
    cylinder(h = h, r = r);
    if (top) translate([0, 0, h]) sphere(r * 1.5);
}
post();
translate([6, 0, 0]) post(8, top = false);
translate([0, 6, 0]) post(r = 2, h = 3);
