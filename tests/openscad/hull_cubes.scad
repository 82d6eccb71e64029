// fragments: 128
// hull of polytopes: cubes turned and moved, a polyhedron (a tetrahedron), a point-like thin box.
hull() {
    cube(2);
    translate([6, 1, 0]) rotate([0, 0, 30]) cube([2, 1, 3]);
    translate([2, 5, 4]) cube(1, center = true);
}
translate([12, 0, 0]) hull() {
    polyhedron([[0, 0, 0], [4, 0, 0], [0, 4, 0], [0, 0, 4]], [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]]);
    translate([3, 3, 3]) cube(0.5);
}
