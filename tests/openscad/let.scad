// let in statements and in expressions.
$fn = 32;
let (r = 3, h = 2 * r) cylinder(h = h, r = r);
size = let (a = 2, b = a + 1) [a, b, a * b];
translate([10, 0, 0]) cube(size);
