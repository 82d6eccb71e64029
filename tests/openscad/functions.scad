// user functions, function literals and built-in functions.
$fn = 32;
function square(x) = x * x;
function offset(v, d = 1) = [for (c = v) c + d];
double = function (x) 2 * x;
for (i = [1 : 3]) translate([square(i), 0, 0]) cube(1 + i * 0.5);
translate(offset([0, 6, 0], 2)) sphere(double(1.5));
translate([0, -6, 0]) cube([max(1, 3), min(4, 2), abs(-2) + sqrt(4)]);
translate([-8, 0, 0]) rotate(atan2(1, 1)) cube([norm([3, 4]), 1, 1]);
