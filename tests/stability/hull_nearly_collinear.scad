// stresses: the hull of three balls whose centres are collinear but for 10⁻⁷, radii growing
// along the line: the two planes tangent to all three are nearly the same plane seen from both
// sides, the cones meet them along slivers.
// expect: ok
// outcome: every check passes (773 samples, on-surface 2.6e-15, nothing unresolved).
$fn = 64;
hull() {
    sphere(1);
    translate([4, 1e-7, 0]) sphere(1.6);
    translate([8, 0, 0]) sphere(2);
}
