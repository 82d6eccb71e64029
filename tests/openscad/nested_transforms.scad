// the order of transforms: the innermost applies first.
$fn = 32;
translate([2, 0, 0]) rotate([0, 0, 45]) scale([1, 2, 1]) translate([3, 0, 0]) cube(2);
rotate([0, 0, 45]) translate([-8, 0, 0]) scale([2, 1, 1]) rotate([0, 90, 0]) cylinder(h = 3, r = 1);
