// import of an STL mesh (a star prism that OpenSCAD exported), relative to this file, under a
// transform and a boolean with a curved solid.
$fn = 64;

difference() {
  rotate([0, 0, 10]) import("lib/star_prism.stl", convexity = 4);
  translate([0, 0, 6]) sphere(3);
  translate([5, 0, -1]) cylinder(h = 8, r = 1);
}
