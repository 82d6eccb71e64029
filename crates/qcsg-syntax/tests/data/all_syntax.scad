// Every construct of the language, for the robustness tests.
include <lib/shapes.scad>
use <lib/util.scad>

/* [Dimensions] */
/// Overall size.
size = 10; // [1:1:20]
$fn = 32;

/** A rounded thing.
 * With two lines of doc.
 */
module thing(r = 1, h = size / 2, center = false) {
    translate([0, 0, center ? -h / 2 : 0])
        cylinder(h = h, r1 = r, r2 = r * 0.5);
    children();
    if ($children > 1) children(1); else echo("one child");
}

function sq(x) = x * x;
function fact(n) = n <= 1 ? 1 : n * fact(n - 1);
function apply(f, v) = [for (x = v) f(x)];
adder = function (a, b = 1) a + b;
pts = [for (i = [0 : 2 : 10]) if (i % 4 == 0) [i, sq(i)] else [i, -i]];
flat = [for (p = pts) each p, 1, each [2, 3]];
cs = [for (i = 0, j = 1; i < 5; i = i + 1, j = j * 2) let (k = i + j) k];
nested = [for (i = [0:3]) for (j = [i:3]) (if (i != j) [i, j])];
v = [1.5, .5, 1e-3, 2.5E+4, "a\"b\\c\n\t\r\x41\u263A", true, false, undef];
m = v[0] + v[1] * v[2] ^ 2 ^ 3 - -v[3] % 2;
logic = !(1 < 2) && 3 >= 2 || 4 != 5 && 6 == 6 && 7 <= 8 && 9 > 1;
chk = assert(size > 0, "size must be positive") size;
dbg = echo("size", size) size + 1;
l = let (a = 1, b = a + 1) [a, b].x;

thing(2) sphere(1);
*thing();
!#%cube(size, center = true);
for (i = [0:3], j = [1, 2]) translate([i * 10, j, 0]) thing(r = i);
intersection_for (k = [0 : 45 : 90]) rotate(k) cube([10, 2, 2], true);
let (q = 3) #for (i = [0:q]) scale(i) sphere();
difference() {
    cube(size);
    % translate([1, 1, -1]) cylinder(h = size + 2, r = 2);
    { sphere(3); }
}
if (size > 5) { cube(1); } else if (size > 2) sphere(1); else ;
assert(len(v) == 8);
echo(fact(5), apply(function (x) x + 1, [1, 2]));
;
