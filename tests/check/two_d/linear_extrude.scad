// 2-D shapes and linear_extrude in the static checks: their signatures come from the table of
// built-in modules. (What no quadric sweeps, `twist` and uneven scales of circles, is found
// when the program runs: crates/qcsg-eval/tests/two_d.rs checks those errors and their spans.)

linear_extrude(height = 3, center = true, convexity = 4, slices = 10, scale = [1, 2]) square([2, 1], center = true);
linear_extrude(5) circle(d = 2);
square(size = "big");
//            ^^^^^ error[E0205]
circle(r = [1, 2]);
//         ^^^^^^ error[E0205]
linear_extrude(3, scale = [1, 2, 3]) square(1);
//                        ^^^^^^^^^ error[E0206]
linear_extrude(height = 3, file = "a.dxf") square(1);
//                         ^^^^^^^^^^^^^^ warning[W0109]: is deprecated
linear_extrude(3, true) square(1);
//                ^^^^ error[E0202]
echo(version(), version_num(), parent_module(0));
