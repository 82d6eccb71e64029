// Part of an include cycle: b includes a back.
include <cycle_a.scad>
//      ^^^^^^^^^^^^^^ error[E0402]: include cycle
b_value = 2;
