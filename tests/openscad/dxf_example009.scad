// import of OpenSCAD's example009.dxf: the body layer (an outline of arcs only, with circular
// holes; its big circle crosses the chords of the outline's arcs), the plate layer (lines, arcs
// and circles) and the fan_top layer (a star of lines and arcs), each extruded.
$fn = 64;

linear_extrude(height = 4, center = true) import(file = "dxf/example009.dxf", layer = "body");
translate([0, 0, 3]) linear_extrude(height = 2) import(file = "dxf/example009.dxf", layer = "plate");
translate([50, 0, 0]) linear_extrude(height = 3) import("dxf/example009.dxf", "fan_top");
