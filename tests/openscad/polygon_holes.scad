// Holes through paths: an outer square with a square and a triangular hole, both listed as
// fragments: 1000000
// further paths (OpenSCAD fills with the even-odd rule whatever the paths' orientation).
linear_extrude(height = 4, center = true)
    polygon(
        points = [[0, 0], [20, 0], [20, 14], [0, 14],
                  [3, 3], [8, 3], [8, 9], [3, 9],
                  [12, 3], [17, 3], [14.5, 11]],
        paths = [[0, 1, 2, 3], [4, 5, 6, 7], [10, 9, 8]]);
