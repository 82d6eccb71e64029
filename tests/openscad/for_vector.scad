// for over a vector of points.
$fn = 32;
for (p = [[0, 0, 0], [6, 2, 0], [3, 7, 1]]) translate(p) sphere(2);
