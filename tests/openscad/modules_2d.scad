// User modules, children(), colour and intersection_for on 2-D shapes.
$fn = 64;
module ring(r, w) difference() { circle(r); circle(r - w); }
module plate(h) linear_extrude(h) children();
plate(2) ring(5, 1);
translate([12, 0, 0]) plate(3) color("red") intersection_for(a = [0, 60, 120]) rotate(a) square([8, 4], center = true);
