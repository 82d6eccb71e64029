// 2-D and 3-D objects do not mix: the first object decides, the others are ignored (with a
// warning in both programs).
// fragments: 1000000
union() {
    cube(3);
    square(10);
}
translate([5, 0, 0]) linear_extrude(2) {
    square(2);
    cube(5);
}
