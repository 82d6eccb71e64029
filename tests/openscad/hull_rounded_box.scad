// hull of eight balls of one radius: the rounded box of OpenSCAD's example006, centred, and a
// turned copy with a hole through it.
$fn = 128;
module rounded_cube(size, r, center = false) {
    s = is_list(size) ? size : [size, size, size];
    translate(center ? -s / 2 : [0, 0, 0])
        hull() {
            for (x = [r, s.x - r], y = [r, s.y - r], z = [r, s.z - r])
                translate([x, y, z]) sphere(r = r);
        }
}
rounded_cube([12, 8, 6], 2, center = true);
translate([16, 0, 0]) rotate([20, 30, 40]) difference() {
    rounded_cube(8, 1.5);
    translate([4, 4, -1]) cylinder(h = 10, r = 2);
}
