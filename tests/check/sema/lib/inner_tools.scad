// Used by tools.scad; a file using tools.scad does not see these (`use` is not transitive).

module inner_tool() sphere(1);
