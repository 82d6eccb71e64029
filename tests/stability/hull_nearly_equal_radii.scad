// stresses: the hull of balls whose radii differ by one part in 10⁹: the tangent cone's apex lies
// some 10⁹ lengths away, written as a frustum whose radius changes linearly along its axis (a
// nearly circular cylinder), beside a third ball of the smaller radius.
// expect: known-failure unresolved
// outcome: the membership is right (the property tests of qcsg-eval's hull_balls check such
// radii against an independent test), but the sampler leaves about 11,600 rectangles unresolved
// (9,700 for radii 1 and 1 + 10⁻⁶; none for radii exactly equal, which are built with circular
// cylinders): the frustum's quadric has eigenvalues 1, 1 and about −β² ≈ −10⁻¹⁸, where the
// conservative distance of a general quadric is weak. Open.
$fn = 64;
hull() {
    sphere(1);
    translate([6, 0, 0]) sphere(1 + 1e-9);
    translate([2, 4, 1]) sphere(1);
}
