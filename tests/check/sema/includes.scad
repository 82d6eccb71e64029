// `include` brings in everything; `use` only modules and functions.

include <lib/shapes.scad>
use <lib/tools.scad>

// Overriding an included default is the customary idiom, not a reassignment.
wall = 1;
shell([wall * 10, 10, 10]);
echo(inner([10, 10, 10]), lib_version);
tool(2);
echo(tool_volume(2));

// `use` does not make variables visible.
echo(tool_size);
//   ^^^^^^^^^ error[E0101]: undefined variable `tool_size`

// `use` is not transitive: what tools.scad uses is not visible here.
inner_tool();
//@ 18:1 error[E0103]: undefined module `inner_tool`

// Arguments of library modules are checked like any other.
tool(m = 2);
//   ^ error[E0201]
shell(size = [1, 2, 3], wall = 3);
//                      ^^^^ error[E0201]

include <lib/missing.scad>
//      ^^^^^^^^^^^^^^^^^^ error[E0401]: cannot find `lib/missing.scad`
use <no_such_library.scad>
//  ^^^^^^^^^^^^^^^^^^^^^^ error[E0401]
