// `use` imports modules and functions (evaluated in their own file); `include` splices text.
use <lib/util.scad>
include <lib/config.scad>
size = 5;
echo(scaled(2), size = size, label = label);
shout("hello");
