// Partial sweeps: counter-clockwise from +x, a reflex angle (a union of two half-spaces), a
// negative angle (clockwise), a shape at x <= 0 (swept from -x, as OpenSCAD does), and an angle
// beyond 360 (a full turn).
$fn = 128;
rotate_extrude(angle = 90) translate([2, 0]) square([3, 2]);
translate([0, 0, 3]) rotate_extrude(angle = 250) translate([1, 0]) square([4, 2]);
translate([0, 0, 6]) rotate_extrude(angle = -120) polygon([[1, 0], [5, 0], [1, 2]]);
translate([0, 0, 9]) rotate_extrude(angle = 100) translate([-5, 0]) square([3, 2]);
translate([0, 0, 12]) rotate_extrude(angle = 400) translate([3, 0]) square([1, 1]);
