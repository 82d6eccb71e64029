// import of a 3MF package with two mesh objects, a box and a roof-shaped prism that overlaps it:
// OpenSCAD 2021.01 unites every mesh object and ignores the build items' transforms (the
// roof's item moves it up by 40, which neither applies). Drilled by a cylinder.
$fn = 64;

difference() {
  import("lib/box_and_roof.3mf");
  translate([3, 2, -1]) cylinder(h = 10, r = 1);
}
