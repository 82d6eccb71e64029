// projection(cut = false) of imported meshes: the STL star prism and the OFF stepped block that
// OpenSCAD exported, tilted and scaled, and one seen from above.
$fn = 64;

linear_extrude(1) projection() {
  rotate([50, 0, 20]) import("lib/star_prism.stl");
  translate([20, 0, 0]) rotate([-35, 25, 0]) scale([1, 1.5, 1]) import("lib/stepped.off");
  translate([0, -20, 4]) import("lib/stepped.off");
}
