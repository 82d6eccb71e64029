// A library for include/use tests.
scale_factor = 10;
function scaled(x) = x * scale_factor;
module shout(s) echo(str(s, "!"));
echo("library top level");
