// rotate_extrude in the static checks: its signature comes from the table of built-in modules.
// (Tori and shapes across the axis are found when the program runs:
// crates/qcsg-eval/tests/rotate_extrude.rs checks those errors and their spans.)

rotate_extrude(angle = 270, convexity = 2) translate([2, 0]) square([1, 2]);
rotate_extrude() polygon([[0, 0], [3, 0], [0, 4]]);
rotate_extrude(angle = "full") square(1);
//                     ^^^^^^ error[E0205]
rotate_extrude(90) square(1);
//             ^^ error[E0202]
rotate_extrude(file = "a.dxf") square(1);
//             ^^^^^^^^^^^^^^ warning[W0109]: is deprecated
