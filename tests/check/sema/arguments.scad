// Arguments checked against built-in signatures (OpenSCAD's names and positional order) and
// against user definitions.

// Built-ins: positional order is OpenSCAD's.
cylinder(10, 2, 1, true);
cylinder(h = 10, r = 2, center = true);
cylinder(h = 10, d1 = 4, d2 = 2);
sphere(2);
sphere(d = 4);
cube([1, 2, 3], true);
rotate(45, [0, 0, 1]) cube(1);
color("red", 0.5) cube(1);
resize([10, 10, 10], auto = true) sphere(1);

cube(1, true, 3);
//            ^ error[E0202]: `cube` takes 2 positional arguments but 3 were given
sphere(2, 3);
//        ^ error[E0202]
cylinder(h = 2, radius = 3);
//              ^^^^^^ error[E0201]: `cylinder` has no parameter `radius`
cube(sise = 2);
//   ^^^^ error[E0201]: `cube` has no parameter `sise`
union(1) cube(1);
//    ^ error[E0202]
cube(size = 1, size = 2);
//             ^^^^ error[E0204]: given more than once
cube(2, size = 3);
//      ^^^^ error[E0204]

// `$`-arguments are accepted by every call, built-in or user-defined.
sphere(1, $fn = 12);
//        ^^^ hint[H0101]
cube(1, $my_setting = 3);

// Built-in functions.
echo(sin(30), atan2(1, 2), pow(2, 3), min(1, 2, 3), max([1, 2]), len("abc"));
echo(str("a", 1, [2]), concat([1], [2, 3]), rands(0, 1, 3, 42), search("a", "abc"));
echo(sin());
//   ^^^ error[E0203]: missing argument `x`
echo(pow(2));
//   ^^^ error[E0203]: `exponent`
echo(sqrt(1, 2));
//           ^ error[E0202]
echo(min());
//   ^^^ error[E0203]: at least 1 argument
// OpenSCAD ignores the names of a built-in function's arguments and uses their order, so
// `atan2(x = 1, y = 2)` would compute atan2(1, 2): names are errors.
echo(norm(v = [3, 4]));
//        ^ error[E0201]: positional arguments only
echo(atan2(x = 1, y = 2));
//         ^ error[E0201]
//                ^ error[E0201]

// User modules and functions.
module bolt(length, diameter = 3, head = true) cylinder(h = length, d = head ? diameter : 1);
function hyp(a, b = 1) = sqrt(a * a + b * b);

bolt(10);
bolt(10, 4, false);
bolt(length = 10, head = false);
bolt(10, $fn = 8);
//       ^^^ hint[H0101]
bolt(10, 4, false, 1);
//                 ^ error[E0202]: module `bolt` takes 3 positional arguments but 4 were given
bolt(10, diamter = 2);
//       ^^^^^^^ error[E0201]: module `bolt` has no parameter `diamter`
bolt(diameter = 2);
//@ 67:1 error[E0203]: missing argument `length`
bolt(10, length = 5);
//       ^^^^^^ error[E0204]
echo(hyp(3, 4), hyp(a = 3));
echo(hyp(1, 2, 3));
//             ^ error[E0202]
echo(hyp(c = 1));
//   ^^^ error[E0203]
//       ^ error[E0201]

// A parameter that is optional says so with a default, `undef` included.
module maybe(x = undef) if (is_undef(x)) cube(1); else cube(x);
maybe();
// ... and so is one the body tests for `undef`, the way OpenSCAD code usually spells it.
module optional_size(size) cube(is_undef(size) ? 1 : size);
optional_size();
function pick(a, b) = b == undef ? a : b;
echo(pick(1));
// A test in a definition nested in the body counts too (it sees the parameter), a test outside
// the body does not.
module outer(p) { module inner() if (is_undef(p)) cube(1); inner(); }
outer();
module strict(p) cube(p);
strict();
//@ 91:1 error[E0203]: missing argument `p`
