// intersection_for: the intersection over the iterations.
$fn = 32;
intersection_for (a = [0, 60, 120]) rotate([0, 0, a]) cube([12, 4, 4], center = true);
translate([0, 15, 0]) intersection_for (i = [0 : 1]) translate([i * 2, 0, 0]) sphere(3);
