// The shape of ../dxf_bulges.scad's drawing (bulges.dxf), written with primitives that OpenSCAD
// 2021.01 draws as the DXF means them.
$fn = 128;

linear_extrude(height = 4) {
  union() {
    difference() {
      square(10);
      translate([5, 15]) circle(r = sqrt(50));
    }
    translate([5, 0]) circle(5);
  }
  union() {
    polygon([[20, 0], [30, 0], [30, 10]]);
    intersection() {
      translate([25, 3.75]) circle(6.25);
      translate([20, -10]) square([10, 10]);
    }
  }
  translate([45, -10]) circle(5);
  difference() {
    translate([40, 10]) square(10);
    translate([50, 15]) circle(5);
  }
}
