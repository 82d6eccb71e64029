// Modules used as functions and the reverse; function literals in variables.

module peg(h = 5) cylinder(h = h, r = 1);
function double(x) = 2 * x;

size = peg(3);
//     ^^^ error[E0104]: `peg` is a module, not a function
echo(size);
volume = cube(2);
//       ^^^^ error[E0104]
echo(volume);
double(3);
//@ 12:1 error[E0105]: `double` is a function, not a module
sqrt(2);
//@ 14:1 error[E0105]
peg(double(2));

// Three namespaces: one name can be a variable, a function and a module at the same time.
part = 3;
function part(n) = n + 1;
module part(n) cube(n);
part(part(part));

// A variable holding a function literal is called like a function.
triple = function (x) 3 * x;
echo(triple(2));
echo(triple(1, 2));
//             ^ error[E0202]: takes 1 positional argument
compose = function (f, g) function (x) f(g(x));
echo(compose(triple, triple)(1));

// Calling something that is not a function.
count = 4;
echo(count(1));
//   ^^^^^ error[E0502]: `count` is a number, not a function
echo([1, 2](0));
//   ^^^^^^ error[E0502]
