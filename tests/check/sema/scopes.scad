// OpenSCAD's scoping rules, none of which is an error.

// Definitions are hoisted: usable before they are written.
early_part(2);
echo(twice(3));
module early_part(s) cube(s);
function twice(x) = 2 * x;

// Instantiations run after every assignment of their scope.
cube(side);
side = 3;

// A bare block is not a scope: its assignments belong to the enclosing scope.
{
    from_block = 4;
}
echo(from_block);

// The children of an instantiation and the branches of an `if` are scopes of their own.
translate([1, 0, 0]) {
    local = 2;
    cube(local);
}
if (side > 2) {
    branch = 1;
    cube(branch);
} else {
    branch = 2;
    sphere(branch);
}

// Later iterators and `let` bindings see the earlier ones.
for (i = [0 : 2], j = [i : 2]) translate([i, j, 0]) cube(1);
echo(let (a = 1, b = a + 1, c = a + b) c);
triangle = [for (i = [0 : 3]) for (j = [0 : i]) [i, j]];
flat = [for (row = triangle) each row];
evens = [for (k = 0; k < 10; k = k + 2) if (k % 4 == 0) k else -k];
echo(triangle, flat, evens);

// Defaults are evaluated in the scope of the definition: they see its variables, even later ones.
module slab(w, d = default_depth) cube([w, d, 1]);
slab(4);
default_depth = 2;

// A module body and a function literal see the whole enclosing scope.
module uses_later() cube(later);
uses_later();
later = 5;
getter = function () after_getter + 1;
after_getter = 2;
echo(getter());

// An assignment reads the enclosing scope's variable when its own scope assigns it later.
outer = 1;
module shadow() {
    copy = outer;
    outer = 2;
    echo(copy, outer);
}
shadow();

// Nested definitions are local to their module.
module assembly(n = 2) {
    module leg(h) cylinder(h = h, r = 0.2);
    function spread(i) = i * 3;
    for (i = [0 : n - 1]) translate([spread(i), 0, 0]) leg(2);
    echo($children);
    children();
}
assembly(3) sphere(1);

// Recursion in functions and modules.
function fact(n) = n <= 1 ? 1 : n * fact(n - 1);
module tower(levels) {
    cube(levels);
    if (levels > 1) translate([0, 0, levels]) tower(levels - 1);
}
echo(fact(5));
tower(3);

// `intersection_for` binds its loop variable for the child.
intersection_for (angle = [0 : 60 : 120]) rotate([0, 0, angle]) cube([3, 1, 1], center = true);

// Built-in constants.
echo(PI * 2);

// A parameter may hold a function literal: a call through it is not checked against the
// built-in function of the same name, which it may be shadowing.
module apply(len) echo(len([1, 2], 3));
apply(function (_v, k) k);
