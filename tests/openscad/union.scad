// union, explicit and implicit (the top level).
$fn = 32;
union() {
    cube(6, center = true);
    sphere(4);
}
translate([10, 0, 0]) { cube(2); translate([1, 1, 1]) cube(2); }
