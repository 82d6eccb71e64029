// projection(cut = false) of a polyhedron: a non-convex prism (an L with a notch, faces clockwise
// seen from outside) tilted so that its walls, top and bottom all cast shadow, mirrored once, and
// united with a ball.
$fn = 64;

l = [[0, 0], [8, 0], [8, 3], [5, 3], [5, 2], [3, 2], [3, 8], [0, 8]];
n = len(l);
module prism()
  polyhedron(
    points = concat([for (q = l) [q[0], q[1], 0]], [for (q = l) [q[0], q[1], 4]]),
    faces = [
      [for (i = [0 : n - 1]) i],
      [for (i = [n - 1 : -1 : 0]) i + n],
      for (i = [0 : n - 1]) [i, i + n, (i + 1) % n + n, (i + 1) % n]
    ]);

linear_extrude(1) projection() {
  rotate([30, 40, 10]) prism();
  translate([20, 0, 3]) mirror([1, 0, 0]) rotate([-60, 15, 0]) prism();
  translate([10, 14, -6]) sphere(3);
}
