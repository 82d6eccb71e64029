// Several independent syntax errors in one file: each is reported at its own place, once, and
// everything between them still parses (and is checked).
size = 2
//      | error[E0002]: expected `;` after assignment
cube(size);
broken = size / ;
//              ^ error[E0002]: expected expression
sphere(size);
translate([1, 2, 3] cube(size);
//                 | error[E0002]: expected `)`
cylinder(h = size, r = 1);
echo(size,, 1);
//        ^ error[E0002]
union() { cube(1); sphere(1) }
//                          | error[E0002]
