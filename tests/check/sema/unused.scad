// Unused names in the main file are warnings; names starting with `_` are exempt.

spare = 3;
//@ 3:1 warning[W0101]: variable `spare` is never used
_ignored = 4;
used = 5;
cube(used);

module unused_module() cube(1);
//     ^^^^^^^^^^^^^ warning[W0103]: module `unused_module` is never instantiated
function unused_function(x) = x;
//       ^^^^^^^^^^^^^^^ warning[W0104]: function `unused_function` is never called
module _private() cube(1);

module part(size, unused_parameter, _reserved) cube(size);
//                ^^^^^^^^^^^^^^^^ warning[W0102]: parameter `unused_parameter` is never used
part(1, 2, 3);

// A recursive function that nothing calls is unused even though it calls itself.
function countdown(n) = n <= 0 ? 0 : countdown(n - 1);
//       ^^^^^^^^^ warning[W0104]

// Unused let variables; loop variables are exempt (they count iterations).
echo(let (a = 1, b = 2) a);
//               ^ warning[W0101]
for (i = [0 : 3]) cube(1);
zeros = [for (i = [0 : 3]) 0];
echo(zeros);

// Variables in a module body.
module body() {
    local = 2;
//  ^^^^^ warning[W0101]
    cube(1);
}
body();

// Function literal parameters.
id = function (x, y) x;
//                ^ warning[W0102]
echo(id(1, 2));
