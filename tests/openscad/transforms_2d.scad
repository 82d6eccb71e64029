// Transforms of 2-D shapes act in the plane: rotate turns about z, translate ignores z, a 3-D
// rotation keeps only its xy part, mirror and multmatrix likewise.
$fn = 64;
linear_extrude(3) {
    translate([5, 0, 7]) rotate(30) square(2);
    mirror([1, 0]) translate([2, 1]) square([1, 3]);
    scale([2, 1]) circle(1);
    translate([0, 6]) rotate([30, 0, 0]) square(2);
    multmatrix([[1, 0.5, 0, 8], [0, 1, 0, 6], [0, 0, 1, 9], [0, 0, 0, 1]]) square(2);
}
