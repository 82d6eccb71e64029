// OpenSCAD's deprecated dxf_linear_extrude: the extrusion of a drawing's layer; its `scale`
// scales the drawing and, as in OpenSCAD 2021.01, the top as well. A cylinder cuts it so that
// the comparison is not of flat parts only.
$fn = 64;

difference() {
  group() {
    dxf_linear_extrude(file = "dxf/example007.dxf", layer = "cutout1", height = 3);
    translate([40, 0, 0])
      dxf_linear_extrude("dxf/example007.dxf", "cutout2", 4, center = true, scale = 0.5);
  }
  translate([1, 8, 0]) cylinder(h = 10, r = 1.5, center = true);
}
