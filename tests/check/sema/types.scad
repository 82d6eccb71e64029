// Values whose type is statically known and definitely wrong.

translate("a") cube(1);
//        ^^^ error[E0205]: `translate` expects a vector of numbers for `v`, found a string
translate([1, 2, 3, 4]) cube(1);
//        ^^^^^^^^^^^^ error[E0206]: `translate` expects `v` to have 2 or 3 elements, found 4
translate([1, 2]) cube(1);
sphere(r = [1, 2]);
//         ^^^^^^ error[E0205]: found a vector of 2 numbers
cube(size = true);
//          ^^^^ error[E0205]
cube([1, 2]);
//   ^^^^^^ error[E0206]
cube(2, center = 1);
//               ^ error[E0205]: a boolean
scale(2) cube(1);
scale([1, 2, 3]) cube(1);
scale("big") cube(1);
//    ^^^^^ error[E0205]
rotate([1, 2, 3, 4]) cube(1);
//     ^^^^^^^^^^^^ error[E0206]
mirror([1, 0, 0]) cube(1);
mirror(1) cube(1);
//     ^ error[E0205]
color([1, 0, 0]) cube(1);
color([1, 0]) cube(1);
//    ^^^^^^ error[E0206]
multmatrix([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]) cube(1);
multmatrix([1, 2]) cube(1);
//         ^^^^^^ error[E0206]
ellipsoid(r = [1, 2, 3]);
halfspace([0, 0, 1], 2);
halfspace(normal = [0, 1]);
//                 ^^^^^^ error[E0206]

// Types flow through variables.
offset = [1, 2, 3];
label = "part";
translate(offset) cube(1);
translate(label) cube(1);
//        ^^^^^ error[E0205]
echo(sin(label));
//       ^^^^^ error[E0205]

// Operators.
a = "a" + 1;
//      ^ error[E0501]: cannot apply `+` to a string and a number
b = true * 2;
//       ^ error[E0501]
c = [1, 2] + 1;
//         ^ error[E0501]
d = -"text";
//  ^ error[E0501]
e = [1, 2] * 2 + [3, 4] - offset;
f = 2 ^ 3 % 2;
g = undef + 1;
//        ^ error[E0501]
echo(a, b, c, d, e, f, g);

// Indexing and members.
n = 5;
echo(n[0]);
//     ^ error[E0503]: cannot index a number
echo(offset["x"]);
//          ^^^ error[E0503]
echo(offset.x, offset.z, label[0]);
echo(offset.w);
//          ^ error[E0504]
echo([1, 2].z);
//          ^ error[E0504]: out of range
echo(n.x);
//     ^ error[E0504]
r = [1 : "b"];
//       ^^^ error[E0501]
echo(r);

// Parameters are of unknown type: nothing is reported for them.
module anything(v) translate(v) cube(v + 1);
anything([1, 2, 3]);

// A function's result type is inferred from its body where it is certain.
translate(label_of(2)) cube(1);
//        ^^^^^^^^^^^ error[E0205]
function label_of(i) = str("part ", i);
function corner(s) = [s, s, s];
translate(corner(2)) cube(1);
translate(label_of(1)) cube(1);
//        ^^^^^^^^^^^ error[E0205]: found a string
function depth(n) = n <= 0 ? 0 : 1 + depth(n - 1);
cube(depth(3));
