// mirror across planes through the origin.
$fn = 32;
mirror([1, 0, 0]) translate([3, 0, 0]) cube([4, 2, 2]);
mirror([1, 1, 0]) translate([2, 5, 0]) cylinder(h = 3, r = 1.5);
mirror(v = [0, 0, 1]) translate([0, 0, 2]) sphere(1.5);
