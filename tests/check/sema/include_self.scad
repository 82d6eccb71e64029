// A file that includes itself.

x = 1;
include <include_self.scad>
//      ^^^^^^^^^^^^^^^^^^^ error[E0402]
echo(x);
