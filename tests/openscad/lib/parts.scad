// A library for the include and use scenes: a module, a function and a variable.
post_height = 4;
function doubled(x) = 2 * x;
module post(h = post_height) cylinder(h = h, r = 1);
cube(1); // geometry of a used file is not instantiated
