// A laser-cut mounting plate in plain OpenSCAD, drawn in 2-D and extruded to the sheet's
// thickness; the file runs unchanged in OpenSCAD 2021.01. Shows: square, circle and polygon;
// 2-D difference; the outline and the slots as 2-D hulls of circles; mirror; linear_extrude.
// Every cut stays exact: straight edges are planes, round ones cylinders, whatever `$fn` says.
// preview: --camera 60,-85,95,0,-3,0 --size 480,360

width = 80;
depth = 50;
sheet = 3;
corner = 6;
hole_d = 4.5;

// A rectangle of the plate's size with rounded corners: the hull of four circles.
module outline() {
    hull()
        for (x = [-1, 1], y = [-1, 1])
            translate([x * (width / 2 - corner), y * (depth / 2 - corner)]) circle(r = corner);
}

// A slot for an adjustable fixing: the hull of two circles.
module slot(length, d) {
    hull() {
        translate([-length / 2, 0]) circle(d = d);
        translate([length / 2, 0]) circle(d = d);
    }
}

linear_extrude(height = sheet)
    difference() {
        outline();
        // Fixing holes in the corners.
        for (x = [-1, 1], y = [-1, 1])
            translate([x * (width / 2 - 7), y * (depth / 2 - 7)]) circle(d = hole_d);
        // Two slots along the long sides.
        for (y = [-1, 1]) translate([0, y * (depth / 2 - 7)]) slot(24, hole_d);
        // A hexagonal opening in the middle and a triangular one each side, mirrored.
        polygon([for (a = [0 : 60 : 300]) 9 * [cos(a), sin(a)]]);
        for (m = [0, 1]) mirror([m, 0]) translate([20, 0])
            polygon([[-4, -7], [6, 0], [-4, 7]]);
    }
