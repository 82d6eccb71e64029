// surface of a .dat height map (rows of numbers, `#` comments, negative heights: the base is one
// below the lowest), centred, cut by a cylinder and united with a turned copy of itself, as
// OpenSCAD's example010 does.
$fn = 64;

difference() {
  union() {
    surface(file = "lib/terrain.dat", center = true, convexity = 5);
    translate([0, 0, -1]) rotate([0, 0, 30]) surface("lib/terrain.dat", true);
  }
  translate([1, 0.5, -10]) cylinder(h = 20, r = 1.1);
}
