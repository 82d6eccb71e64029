// stresses: the hull of a ball with a smaller ball inside it touching it from inside, a ball at
// the same centre, and a ball apart: the inner balls add nothing and are dropped.
// expect: ok
// outcome: every check passes (671 samples, on-surface 1.4e-16, nothing unresolved).
$fn = 64;
hull() {
    sphere(3);
    translate([2, 0, 0]) sphere(1);
    sphere(1);
    translate([0, 8, 0]) sphere(0.5);
}
