// A self-intersecting pentagram drawn in one stroke, turned and extruded: the even-odd rule
// fragments: 1000000
// leaves its central pentagon empty.
linear_extrude(5)
    rotate(10) translate([1, -2])
        polygon([for (k = [0 : 4]) 10 * [cos(90 + 144 * k), sin(90 + 144 * k)]]);
