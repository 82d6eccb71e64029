// hull of eight balls of one radius: the rounded box of OpenSCAD's example006, turned and moved
// (one object: OpenSCAD's union of such meshes takes minutes).
$fn = 128;
module rounded_cube(size, r, center = false) {
    s = is_list(size) ? size : [size, size, size];
    translate(center ? -s / 2 : [0, 0, 0])
        hull() {
            for (x = [r, s.x - r], y = [r, s.y - r], z = [r, s.z - r])
                translate([x, y, z]) sphere(r = r);
        }
}
translate([3, 2, 1]) rotate([20, 30, 40]) rounded_cube([12, 8, 6], 2, center = true);
