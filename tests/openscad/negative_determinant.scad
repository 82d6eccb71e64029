// mirrors and negative scales inside differences: orientation must not flip the solid.
$fn = 32;
difference() {
    scale([-1, 1, 1]) cube([6, 6, 6]);
    mirror([0, 1, 0]) translate([-3, -3, 3]) sphere(2.5);
}
translate([0, 10, 0]) scale([1, -2, 1]) cylinder(h = 2, r = 2);
