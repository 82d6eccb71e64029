// A plate with round holes, made in 2-D and extruded once.
$fn = 64;
linear_extrude(2) difference() {
    square([20, 10]);
    for (x = [4 : 6 : 16]) translate([x, 5]) circle(2);
}
