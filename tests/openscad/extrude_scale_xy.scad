// Different scales in x and y: exact for straight edges, a turned square included. Its sides
// are hyperbolic paraboloids, which OpenSCAD approximates slice by slice (hence the slices and
// the tolerance).
// fragments: 64
linear_extrude(4, scale = [2, 0.5]) square([3, 2]);
translate([12, 0, 0]) linear_extrude(3, scale = [0.5, 1.5], slices = 100) rotate(30) square(3, center = true);
