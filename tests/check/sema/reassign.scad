// The last assignment in a scope wins for the whole scope.

size = 1;
cube(size);
size = 2;
//@ 5:1 warning[W0105]: `size` is assigned again

// Every reader sees the last value, even one before it.
module m() {
    r = 1;
    sphere(r);
    r = 3;
//  ^ warning[W0105]
}
m();

// A different scope is not a reassignment: it shadows.
module n() {
    size = 5;
    cube(size);
}
n();
