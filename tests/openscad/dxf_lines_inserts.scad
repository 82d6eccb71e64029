// import of drawings of lines: example013.dxf (four INSERTs of two blocks, rotated), a layer of
// example008.dxf with two holes, moved by origin and halved by scale, and a layer of
// example007.dxf; the curves are straight, so OpenSCAD's fragments do not matter.
// fragments: 200

linear_extrude(height = 10) import("dxf/example013.dxf");
translate([0, 0, 12]) linear_extrude(height = 5)
  import(file = "dxf/example008.dxf", layer = "B", origin = [100, 100], scale = 0.5);
translate([40, 0, 0]) linear_extrude(height = 5) import(file = "dxf/example007.dxf", layer = "cutout2");
