// (A ∩ B) ∪ C: the lens of two unit balls with a third ball through it (3 quadrics, the first
// scene of paper 000's Table 2).
union() {
    intersection() {
        translate([-0.4, 0, 0]) sphere(1);
        translate([0.4, 0, 0]) sphere(1);
    }
    translate([0, 0.9, 0.3]) sphere(0.6);
}
