// Uniform scales: frusta of a centred square and of an off-centre square, whose sections scale
// about the z axis (so it leans outwards), and a growing disc.
$fn = 64;
linear_extrude(6, scale = 0.5) square(6, center = true);
translate([10, 0, 0]) linear_extrude(height = 10, scale = 2) translate([2, 0]) square(1);
translate([0, 12, 0]) linear_extrude(height = 4, center = true, scale = 1.5) circle(2);
