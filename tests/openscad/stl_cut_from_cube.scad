// An imported STL mesh (a star prism), twice, cut out of a block: a difference whose subtracted
// parts are unions of convex mesh cells.
// fragments: 1000000
difference() {
    cube([30, 24, 8], center = true);
    translate([-6, 0, -5]) rotate([0, 0, 10]) import("lib/star_prism.stl", convexity = 4);
    translate([7, 3, -7]) rotate([0, 0, -25]) scale([0.8, 0.8, 2]) import("lib/star_prism.stl");
}
