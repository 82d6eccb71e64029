// user modules with children(), children(i) and $children.
$fn = 32;
module row(n) for (i = [0 : n - 1]) translate([i * 5, 0, 0]) children();
row(3) sphere(2);
module pair() {
    children(0);
    translate([0, 8, 0]) children(1);
    if ($children > 2) translate([0, 16, 0]) children([2 : $children - 1]);
}
pair() { cube(2); sphere(1.5); cube([3, 1, 1]); translate([4, 0, 0]) cube(1); }
