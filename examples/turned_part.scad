// A turned part in plain OpenSCAD: a candle holder drawn as its half-section in the (r, z)
// plane and swept about the z axis by rotate_extrude; the file runs unchanged in OpenSCAD
// 2021.01. Shows: polygon and circle outlines; 2-D union, difference and scale; and
// rotate_extrude with `angle`, here 270° so that the cut-away shows the section. Each edge of
// the outline sweeps its own quadric: slanted edges cones, vertical ones cylinders, horizontal
// ones planes, and a circle or an ellipse centred on the axis a sphere or ellipsoid.
// preview: --camera 70,-95,70,0,0,22 --size 480,360

foot_r = 26;
stem_r = 6;
cup_r = 16;
height = 48;
bore_r = 10;

// The half-section: x is the radius, y the height.
module section() {
    difference() {
        union() {
            // The foot, a stepped and tapered disc.
            polygon([[0, 0], [foot_r, 0], [foot_r, 3], [foot_r - 4, 6], [stem_r + 2, 10],
                [0, 10]]);
            // The stem.
            square([stem_r, height - 10]);
            // A flattened knob on the stem, an ellipse centred on the axis, and a ball under it.
            translate([0, 22]) scale([1, 0.6]) circle(r = 11);
            translate([0, 13]) circle(r = 8);
            // The cup, a flared bowl under a flat lip.
            polygon([[0, height - 18], [stem_r, height - 18], [cup_r, height - 4],
                [cup_r, height], [0, height]]);
        }
        // The socket for the candle.
        translate([0, height - 10]) square([bore_r, 11]);
    }
}

// The outline must lie on one side of the axis, as OpenSCAD requires: the circles centred on it
// are cut to their right halves.
rotate_extrude(angle = 270)
    intersection() {
        section();
        square([foot_r, height]);
    }
