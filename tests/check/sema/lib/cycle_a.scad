// Part of an include cycle: a includes b, b includes a.
include <cycle_b.scad>
a_value = 1;
