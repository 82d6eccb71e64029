// A turned part from one outline swept about z: a lower hemisphere (a quarter disc on the axis),
// a cylinder, a cone (a triangle), a groove cut by a rectangle, and a ball cap on top (a disc
// centred on the axis, cut to x >= 0).
$fn = 128;
rotate_extrude() difference() {
    union() {
        intersection() { circle(5); translate([0, -5]) square(5); }
        square([4, 8]);
        polygon([[0, 8], [4, 8], [0, 12]]);
        intersection() { translate([0, 11]) circle(2); translate([0, 9]) square([3, 5]); }
    }
    translate([3, 3]) square([2, 1.5]);
}
