// $-variables are dynamically scoped: set at a call, seen by the callee.
$fn = 32;
module ball() sphere($size);
module nested() ball();
ball($size = 3);
translate([10, 0, 0]) nested($size = 2);
$size = 1;
translate([0, 10, 0]) ball();
