// recursive modules and functions.
$fn = 32;
module tower(n) {
    cube([n, n, 1]);
    if (n > 1) translate([0.5, 0.5, 1]) tower(n - 1);
}
tower(5);
function total(v, i = 0) = i >= len(v) ? 0 : v[i] + total(v, i + 1);
translate([10, 0, 0]) cylinder(h = total([1, 2, 3]), r = 2);
