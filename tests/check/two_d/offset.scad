// offset in the static checks: its signature comes from the table of built-in modules. (What
// has no exact offset is found when the program runs: crates/qcsg-eval/tests/offset.rs checks
// that error.)

linear_extrude(1) offset(r = 1) square(2);
linear_extrude(1) offset(1) circle(2);
linear_extrude(1) offset(delta = 0.5, chamfer = true) square(2);
offset(r = "wide") square(1);
//         ^^^^^^ error[E0205]
offset(1, 2) square(1);
//        ^ error[E0202]
