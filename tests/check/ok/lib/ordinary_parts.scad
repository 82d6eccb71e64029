// Parts shared by ordinary.scad, included the way OpenSCAD projects usually do it.

/// Clearance added around holes.
clearance = 0.2;

/// A round peg of height h and diameter d, centred on the XY plane.
module peg(h = 10, d = 4) {
    cylinder(h = h, d = d + clearance, center = true);
}

/// Positions of n points evenly spaced on a circle of radius r.
function circle_points(n, r) = [for (i = [0 : n - 1]) [r * cos(360 * i / n), r * sin(360 * i / n), 0]];
