// Stray closing delimiters, and a missing include path.
cube(1);
)
//@ 3:1 error[E0009]: unexpected closing delimiter
sphere(1); ]
//         ^ error[E0009]
include cube;
//      ^^^^ error[E0010]: expected `<path>`
