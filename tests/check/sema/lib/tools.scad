// Used (not included) by the include/use cases: only its modules and functions are visible.

tool_size = 5;

module tool(n = 1) cube(tool_size * n);
function tool_volume(n = 1) = pow(tool_size * n, 3);
