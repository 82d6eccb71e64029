// Include cycles are reported at the include that closes the cycle.

include <lib/cycle_a.scad>
echo(a_value, b_value);
