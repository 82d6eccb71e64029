// OpenSCAD's deprecated dxf_linear_extrude and dxf_rotate_extrude: the extrusions of a drawing's
// layer; dxf_linear_extrude's `scale` scales the drawing and, as in OpenSCAD 2021.01, the top as
// well; dxf_rotate_extrude's `origin` moves the drawing off the axis; and the extrusions' own
// deprecated `file` argument, which reads the drawing in place of the children. A cylinder cuts it so that
// the comparison is not of flat parts only.
$fn = 64;

difference() {
  group() {
    dxf_linear_extrude(file = "dxf/example007.dxf", layer = "cutout1", height = 3);
    translate([40, 0, 0])
      dxf_linear_extrude("dxf/example007.dxf", "cutout2", 4, center = true, scale = 0.5);
    translate([0, -60, 0])
      dxf_rotate_extrude("dxf/example007.dxf", "cutout2", [-12, 0], 1, angle = 90);
    translate([-40, 0, 0])
      linear_extrude(height = 2, file = "dxf/example007.dxf", layer = "cutout2", scale = 0.8);
    translate([-40, -60, 0])
      rotate_extrude(file = "dxf/example007.dxf", layer = "cutout2", origin = [12, 0]) cube(1);
  }
  translate([1, 8, 0]) cylinder(h = 10, r = 1.5, center = true);
}
