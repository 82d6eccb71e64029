// A block comment without its end runs to the end of the file.
cube(1);
/* never closed
//@ 3:1 error[E0005]: unterminated block comment
sphere(1);
