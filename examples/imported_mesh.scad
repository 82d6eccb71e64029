// An imported mesh: a faceted vase body read from an OFF file (a polygon mesh, as a scanner or
// another modeller writes it), hollowed and drilled with quadrics. The file runs unchanged in
// OpenSCAD 2021.01. Shows: import() of a mesh (STL or OFF), found relative to this file; a
// non-convex polyhedron read exactly as a boolean of its face planes; booleans between a mesh
// and round solids, whose faces stay exact cylinders and spheres.
// preview: --camera 95,-120,130,0,0,30 --size 480,360

neck_d = 22;
drain_d = 5;

difference() {
    import("faceted_vase.off");
    // The bore down the neck, ending in a ball so that the bottom of the cavity is round.
    translate([0, 0, 30]) cylinder(h = 50, d = neck_d);
    translate([0, 0, 30]) sphere(d = neck_d);
    // A wider chamber in the belly, a ball inside the facets.
    translate([0, 0, 24]) sphere(r = 19);
    // The drain hole through the foot.
    translate([0, 0, -1]) cylinder(h = 10, d = drain_d);
}
