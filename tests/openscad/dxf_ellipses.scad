// import of ELLIPSE entities (dxf/ellipses.dxf): a full ellipse rotated by its axis vector, a
// rotated elliptic hole in a rectangle, half an ellipse and a rotated partial one (each closed
// by its chord, as OpenSCAD closes open paths), and a slot whose ends are half ellipses that
// meet two lines; above, the drawing cut by a square. OpenSCAD cuts each ellipse into $fn fragments; qcsg reads them exactly.
$fn = 128;

linear_extrude(height = 4) import("dxf/ellipses.dxf");
translate([0, 0, 6]) linear_extrude(height = 2) intersection() {
  import("dxf/ellipses.dxf");
  translate([-4, -10]) square([40, 40]);
}
