// linear_extrude of squares: the shape cut by the slab 0 <= z <= h, the height given by name,
// by position and centred.
// fragments: 1000000
linear_extrude(height = 5) square([4, 3]);
translate([6, 0, 0]) linear_extrude(2) square(3, center = true);
translate([0, 6, 0]) linear_extrude(4, center = true) square([2, 5]);
