// An angle bracket in plain OpenSCAD: this file runs unchanged in OpenSCAD 2021.01
// (`openscad -o bracket.stl openscad_bracket.scad`) and in qcsg, and means the same in both.
// Shows: the .scad subset qcsg accepts (cube, cylinder, sphere, the transforms, the booleans,
// for loops, modules with defaults), and a triangular gusset made without polygon(): a box cut
// diagonally by a rotated box, since linear_extrude() of a 2-D shape is not a quadric solid.
// preview: --camera iso --size 480,360

length = 50;        // along x
leg = 30;           // height of the upright leg and depth of the base
thickness = 5;
hole_d = 5.5;
gusset_width = 4;

// A hole through a plate of thickness t, along z.
module hole(t, d = hole_d) {
    translate([0, 0, -1]) cylinder(h = t + 2, d = d);
}

// A right-triangular gusset of legs a, of width w, in the y-z plane: the box [w, a, a]
// keeps the part below its diagonal plane y + z <= a.
module gusset(a, w) {
    difference() {
        cube([w, a, a]);
        translate([-1, a, 0]) rotate([45, 0, 0]) cube([w + 2, a * 2, a * 2]);
    }
}

difference() {
    union() {
        cube([length, leg, thickness]);                                   // base
        translate([0, leg - thickness, 0]) cube([length, thickness, leg]);  // upright leg
        // Gussets in front of the leg: mirrored so that their legs run along -y and +z.
        for (x = [thickness, length - thickness - gusset_width])
            translate([x, leg - thickness, 0]) mirror([0, 1, 0]) gusset(leg * 0.7, gusset_width);
    }
    // Two holes in the base, two in the leg.
    for (x = [length * 0.3, length * 0.7]) {
        translate([x, leg * 0.35, 0]) hole(thickness);
        translate([x, leg - thickness, leg * 0.65]) rotate([-90, 0, 0]) hole(thickness);
    }
}
