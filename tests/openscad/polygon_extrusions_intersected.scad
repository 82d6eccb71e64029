// The intersection of two extruded polygons at right angles: a 40-point star and a comb, each a
// union of many convex cells.
// fragments: 1000000
intersection() {
    linear_extrude(height = 30, center = true)
        polygon([for (k = [0 : 39]) (k % 2 == 0 ? 14 : 8) * [cos(9 * k), sin(9 * k)]]);
    rotate([90, 0, 0])
        linear_extrude(height = 40, center = true)
            polygon(concat(
                [[-16, -12], [16, -12]],
                [for (i = [7 : -1 : -8]) each [[2 * i + 1.5, 12], [2 * i + 1, 3], [2 * i, 3]]]
            ));
}
