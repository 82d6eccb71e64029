// A string without its closing quote runs to the end of the file; nothing after it is reported
// again.
cube(1);
echo("never closed);
//   ^ error[E0003]: unterminated string
sphere(1);
