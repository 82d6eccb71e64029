// Names that resolve nowhere: variables, functions and modules each have their own namespace.

width = 10;
depth = 4;
cube([width, depht, 2]);
//           ^^^^^ error[E0101]: undefined variable `depht`
cube(height);
//   ^^^^^^ error[E0101]: undefined variable `height`

function area(w, d) = w * d;
echo(aera(width, depth));
//   ^^^^ error[E0102]: undefined function `aera`
echo(nothing_like_this(1));
//   ^^^^^^^^^^^^^^^^^ error[E0102]

module plate(size) cube(size);
plat(3);
//@ 17:1 error[E0103]: undefined module `plat`
plate(area(1, 2));

// A function is not a value: reading its name as a variable is an error with a hint.
f = area;
//  ^^^^ error[E0101]
echo(f);

// A module is not a value either.
g = plate;
//  ^^^^^ error[E0101]
echo(g);

// Loop, let and parameter names are local to their scope.
for (i = [0 : 2]) translate([i, 0, 0]) cube(1);
echo(i);
//   ^ error[E0101]
z = let (k = 2) k * 2;
echo(z, k);
//      ^ error[E0101]
module holder(r = 1) sphere(r);
holder();
echo(r);
//   ^ error[E0101]

// Assignments in a scope run in order: reading a variable assigned later gives `undef`.
early = late + 1;
//      ^^^^ error[E0106]: read before it is assigned
late = 2;
echo(early);

// Parameter defaults are evaluated where the definition is, so they cannot read other parameters.
module slab(w, d = w / 2) cube([w, d, 1]);
//                 ^ error[E0101]: undefined variable `w`
slab(4);
function half(x, y = x) = (x + y) / 2;
//                   ^ error[E0101]
echo(half(3));
