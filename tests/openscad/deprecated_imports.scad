// OpenSCAD's deprecated group() (a union) and import_stl, import_off, import_dxf (import under
// old names), with a curved solid so that the comparison is not of flat parts only.
$fn = 64;

group() {
  difference() {
    rotate([0, 0, 10]) import_stl("lib/star_prism.stl", convexity = 4);
    translate([0, 0, 6]) sphere(3);
  }
  translate([0, -25, 0]) import_off(file = "lib/stepped.off");
  translate([30, 0, 0]) linear_extrude(height = 2) import_dxf("dxf/example007.dxf", "cutout1");
}
