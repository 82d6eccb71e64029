// polyhedron: a non-convex prism (an L with a notch), faces clockwise seen from outside as
// OpenSCAD's manual asks, a tetrahedron given with the deprecated `triangles`, and a cut by a
// cylinder.
$fn = 64;

l = [[0, 0], [8, 0], [8, 3], [5, 3], [5, 2], [3, 2], [3, 8], [0, 8]];
n = len(l);
difference() {
  polyhedron(
    points = concat([for (q = l) [q[0], q[1], 0]], [for (q = l) [q[0], q[1], 4]]),
    faces = [
      [for (i = [0 : n - 1]) i],
      [for (i = [n - 1 : -1 : 0]) i + n],
      for (i = [0 : n - 1]) [i, i + n, (i + 1) % n + n, (i + 1) % n]
    ]);
  translate([1.5, 5, -1]) cylinder(h = 6, r = 1);
}
translate([10, 0, 0])
  polyhedron(points = [[0, 0, 0], [4, 0, 0], [0, 4, 0], [0, 0, 4]],
             triangles = [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]]);
