// 1,000 primitive instances through the language: 500 spheres, 250 cylinders and 250 cubes on
// a 10 × 10 × 10 grid, placed by a module with transforms, a function and nested loops.
function spot(i, j, k) = [i * 4, j * 4, k * 4];
module part(kind, size) {
    if (kind == 0) sphere(r = size);
    else if (kind == 1) rotate([90, 0, 30]) cylinder(h = 2 * size, r = size / 2, center = true);
    else rotate([0, 0, 45]) cube(size, center = true);
}
for (i = [0 : 9], j = [0 : 9], k = [0 : 9])
    translate(spot(i, j, k))
        part(kind = (i + j + k) % 2 == 0 ? 0 : (i % 2 == 0 ? 1 : 2), size = 1 + (i + j) / 20);
