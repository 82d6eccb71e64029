// Used (not included) by the include/use cases: only its modules and functions are visible.

use <inner_tools.scad>

tool_size = 5;

module tool(n = 1) {
    cube(tool_size * n);
    inner_tool();
}
function tool_volume(n = 1) = pow(tool_size * n, 3);
