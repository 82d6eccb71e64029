// surface of a PNG image (luminance 0 to 100, the image's top row at the largest y), scaled
// flat, beside the inverted map (1 - L on the 0-255 scale: heights near -100) lifted back up.
$fn = 64;

union() {
  scale([1, 1, 0.05]) surface(file = "lib/terrain.png");
  translate([8, 0, 6]) scale([1, 1, 0.05]) surface(file = "lib/terrain.png", invert = true);
  translate([2, 2, 5]) sphere(1);
}
