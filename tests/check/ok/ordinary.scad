// A bracket with a ring of pegs, written the way ordinary OpenSCAD files are.
include <lib/ordinary_parts.scad>

$fn = 48;
//@ 4:1 hint[H0101]

/* [Dimensions] */
plate_size = [40, 30, 4]; // [10:100]
peg_count = 6;
ring_radius = 10;
fillet = 1;

/// Sum of a vector, recursively.
function sum(v, i = 0) = i >= len(v) ? 0 : v[i] + sum(v, i + 1);

/// Clamps x into [lo, hi].
function clamp(x, lo = 0, hi = 1) = min(max(x, lo), hi);

// A function literal kept in a variable, and one returned by a function.
scale_by = function (k) function (x) x * k;
half = scale_by(0.5);

/// Places its children at every point of `points`.
module place_at(points) {
    for (p = points) translate(p) children();
}

/// Mirrors its children across X and Y (four copies).
module quadrants() {
    for (mx = [0, 1], my = [0, 1]) mirror([mx, 0, 0]) mirror([0, my, 0]) children();
}

module plate(size, holes = true) {
    difference() {
        cube(size, center = true);
        if (holes) {
            quadrants() translate([size.x / 2 - 4, size.y / 2 - 4, 0]) cylinder(h = size.z * 2, r = 1.5, center = true);
        } else {
            echo("plate without holes");
        }
    }
}

heights = [for (i = [0 : peg_count - 1]) let (t = i / (peg_count - 1)) 4 + 6 * clamp(t, 0.2, 0.8)];
odd_heights = [for (i = [0 : len(heights) - 1]) if (i % 2 == 1) heights[i]];
total = sum(heights);
grid = [for (x = [0 : 2], y = [0 : 1]) [x * 10, y * 10]];
squares = [for (i = 0; i < 5; i = i + 1) i * i];
flat = [for (row = [[1, 2], [3]]) each row];
assert(total > 0, "heights must be positive");
echo(total = total, odd = odd_heights, grid = grid, squares = squares, flat = flat, half = half(10));

union() {
    plate(plate_size);
    translate([0, 0, plate_size.z / 2]) place_at(circle_points(peg_count, ring_radius)) {
        peg(h = heights[0], d = 3);
        sphere(r = fillet, $fn = 24);
//                         ^^^ hint[H0101]
    }
    rotate([0, 0, 45]) translate([0, 0, -plate_size[2]]) scale([1, 1, 0.5]) ellipsoid(r = [5, 4, 3]);
    color("steelblue", 0.8) intersection() {
        sphere(d = 12);
        cube(10, center = true);
    }
}

# translate([30, 0, 0]) cylinder(h = 5, r1 = 3, r2 = 0);
