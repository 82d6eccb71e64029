// import of polylines with bulges (dxf/bulges.dxf): a closed LWPOLYLINE with a positive bulge
// (a half circle out of its bottom edge) and a negative one (a quarter-turn arc into its top
// edge), an open LWPOLYLINE whose bulged first edge is an arc (closed by a straight edge), and
// closed POLYLINEs whose VERTEX bulges make a disc and bite a half disc out of a square. A bulge
// is the tangent of a quarter of the arc's angle, counter-clockwise when positive. OpenSCAD
// 2021.01 draws the chords of bulged edges, so the mesh compared is that of
// dxf/bulges_reference.scad, the same shape written with squares, circles and polygons.
// reference: dxf/bulges_reference.scad
$fn = 128;

linear_extrude(height = 4) import("dxf/bulges.dxf");
