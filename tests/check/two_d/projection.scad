// projection in the static checks: its signature comes from the table of built-in modules.
// (Shadows not computed exactly are found when the program runs:
// crates/qcsg-eval/tests/projection.rs checks that error.)

linear_extrude(1) projection(cut = true, convexity = 2) sphere(3);
linear_extrude(1) projection() cube(2);
projection(cut = 1) sphere(1);
//               ^ error[E0205]
projection(true) sphere(1);
//         ^^^^ error[E0202]
