// A plate with a 100-point star cut out of it: the star is a polygon of many convex cells, and
// the difference is built from the cells of its complement, not from the product of the cells'
// complements.
// fragments: 1000000
linear_extrude(height = 3)
    difference() {
        square([60, 60], center = true);
        rotate(7) polygon([for (k = [0 : 99]) (k % 2 == 0 ? 25 : 13) * [cos(3.6 * k), sin(3.6 * k)]]);
    }
