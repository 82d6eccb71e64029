// multmatrix: a shear and a full affine 4x4, and a 3x4.
$fn = 32;
multmatrix([[1, 0.5, 0, 2], [0, 1, 0, 0], [0, 0.3, 1, 1], [0, 0, 0, 1]]) cube([4, 4, 4]);
translate([12, 0, 0]) multmatrix(m = [[0, -1, 0, 0], [1, 0, 0, 0], [0, 0, 2, 0]]) sphere(2);
