// polygon in the static checks: its signature comes from the table of built-in modules. (Bad
// points and path entries are found when the program runs: crates/qcsg-eval/tests/polygon.rs
// checks those errors.)

polygon([[0, 0], [1, 0], [0, 1]]);
polygon(points = [[0, 0], [4, 0], [4, 4], [0, 4], [1, 1], [2, 1], [1, 2]], paths = [[0, 1, 2, 3], [4, 5, 6]], convexity = 2);
polygon(points = 3);
//               ^ error[E0205]
polygon([[0, 0], [1, 0], [0, 1]], closed = true);
//                                ^^^^^^ error[E0201]
