// use imports definitions only; include splices the file in.
$fn = 32;
use <lib/parts.scad>
include <lib/settings.scad>
cube(block);
translate([6, 0, 0]) post(doubled(2));
