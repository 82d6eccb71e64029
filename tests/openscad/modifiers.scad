// modifiers: % (background) and * (disabled) are not in the solid; # is.
$fn = 32;
cube(4);
%translate([10, 0, 0]) sphere(3);
*translate([0, 10, 0]) cube(3);
#translate([0, 0, 6]) sphere(2);
