// A rounded enclosure with a lid, in plain OpenSCAD: the rounding idioms of hull and minkowski,
// exact. The box is the hull of four vertical cylinders (a plate with rounded corners), hollowed
// by a smaller box summed with a cylinder (its inside, with the corners' rounding less the wall);
// the lid is a flat box summed with a ball (rounded top edges and corners), cut flat below and
// hollowed the same way, with a lip that fits inside the box. Screw bosses stand in the corners,
// and a cable hole goes through one end. The lid floats above the box, as in an exploded view;
// the file runs unchanged in OpenSCAD 2021.01.
// preview: --camera 100,-120,140,30,20,24 --size 480,360

size = [60, 40, 24];   // the box's outside
r = 6;                 // the corners' rounding
wall = 2;
lid_top = 2;           // the lid's height above its rounded edges
gap = 20;              // how far the lid floats above the box
boss_r = 3.5;
screw_r = 1.2;
bosses = [for (x = [wall + boss_r, size.x - wall - boss_r],
    y = [wall + boss_r, size.y - wall - boss_r]) [x, y]];

// A plate of `s` with corners rounded by `rc`, `h` high: the hull of four vertical cylinders.
module rounded_plate(s, rc, h) {
    hull() for (x = [rc, s.x - rc], y = [rc, s.y - rc])
        translate([x, y, 0]) cylinder(r = rc, h = h);
}

// The inside of a wall of thickness `w` of `rounded_plate(s, rc, …)`, from z0 to z1: a box
// summed with a cylinder of the rounding less the wall.
module inside(s, rc, w, z0, z1) {
    minkowski() {
        translate([rc, rc, z0]) cube([s.x - 2 * rc, s.y - 2 * rc, z1 - z0 - 1]);
        cylinder(r = rc - w, h = 1);
    }
}

module box() {
    difference() {
        union() {
            difference() {
                rounded_plate(size, r, size.z);
                inside(size, r, wall, wall, size.z + 1);
            }
            for (b = bosses) translate([b.x, b.y, 0]) cylinder(r = boss_r, h = size.z - 3);
        }
        for (b = bosses) translate([b.x, b.y, wall]) cylinder(r = screw_r, h = size.z);
        // The cable hole through the end at x = 0.
        translate([-1, size.y / 2, size.z / 2]) rotate([0, 90, 0]) cylinder(r = 3, h = wall + 2);
    }
}

module lid() {
    difference() {
        // A flat box summed with a ball: rounded top edges and corners, cut flat below.
        intersection() {
            minkowski() {
                translate([r, r, 0]) cube([size.x - 2 * r, size.y - 2 * r, lid_top]);
                sphere(r);
            }
            translate([-1, -1, 0]) cube([size.x + 2, size.y + 2, lid_top + r + 1]);
        }
        // Hollowed the same way under the rounded top, `wall` thick.
        minkowski() {
            translate([r, r, -r]) cube([size.x - 2 * r, size.y - 2 * r, lid_top + r]);
            sphere(r - wall);
        }
        for (b = bosses) translate([b.x, b.y, -1]) cylinder(r = screw_r + 0.3, h = lid_top + r + 2);
    }
    // The lip, a ring that fits inside the box, and a boss over each screw hole.
    difference() {
        inside(size, r, wall + 0.3, -3, 0);
        inside(size, r, 2 * wall + 0.3, -4, 1);
    }
    for (b = bosses) translate([b.x, b.y, 0]) difference() {
        cylinder(r = boss_r, h = lid_top + r - wall);
        translate([0, 0, -1]) cylinder(r = screw_r + 0.3, h = lid_top + r);
    }
}

box();
translate([0, 0, size.z + gap]) lid();
