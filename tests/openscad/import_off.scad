// import of an OFF mesh (a stepped block that OpenSCAD exported) by name, scaled and mirrored
// (the faces stay outward), united with a ball.
$fn = 64;

union() {
  mirror([1, 0, 0]) scale([1, 1.5, 1]) import(file = "lib/stepped.off");
  translate([-2, 6, 7]) sphere(1.5);
}
