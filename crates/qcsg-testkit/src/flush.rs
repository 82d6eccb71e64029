//! Solids written two ways: with surfaces shared by their parts (a cutter flush with a face, a
//! ball minus a turned copy of itself) and without. Every consumer of the DNF must show the
//! flush scene as its clean twin; the ray tracer's, the splats' and the sampler's tests read
//! this one list.

use glam::DVec3;

/// One solid, flush and clean, and a view of it.
#[derive(Clone, Copy, Debug)]
pub struct FlushPair {
    /// What the pair shows.
    pub name: &'static str,
    /// The solid with parts that share surfaces.
    pub flush: &'static str,
    /// The same solid without shared surfaces (empty where the flush solid is empty).
    pub clean: &'static str,
    /// A point the camera looks at.
    pub centre: DVec3,
    /// From `centre` towards the eye.
    pub towards_eye: DVec3,
    /// How far the eye is from `centre`.
    pub distance: f64,
}

/// Every pair. The skew-turned notch is centred on the origin so that a view of the origin
/// frames it.
pub const FLUSH_PAIRS: &[FlushPair] = &[
    FlushPair {
        name: "notch",
        flush: "difference() { cube([20, 10, 10]); translate([5, 0, 5]) cube([10, 10, 5]); }",
        clean: "difference() { cube([20, 10, 10]); translate([5, -1, 5]) cube([10, 12, 6]); }",
        centre: DVec3::new(10.0, 5.0, 5.0),
        towards_eye: DVec3::new(0.5, -1.0, 0.9),
        distance: 60.0,
    },
    FlushPair {
        name: "notch turned by 37 degrees",
        flush: "rotate([0, 0, 37]) difference() { cube([20, 10, 10]); translate([5, 0, 5]) cube([10, 10, 5]); }",
        clean: "rotate([0, 0, 37]) difference() { cube([20, 10, 10]); translate([5, -1, 5]) cube([10, 12, 6]); }",
        centre: DVec3::new(10.0, 5.0, 5.0),
        towards_eye: DVec3::new(0.5, -1.0, 0.9),
        distance: 60.0,
    },
    FlushPair {
        name: "notch turned about a skew axis",
        flush: "rotate([37, 37, 0]) translate([-10, -5, -5]) difference() { cube([20, 10, 10]); translate([5, 0, 5]) cube([10, 10, 5]); }",
        clean: "rotate([37, 37, 0]) translate([-10, -5, -5]) difference() { cube([20, 10, 10]); translate([5, -1, 5]) cube([10, 12, 6]); }",
        centre: DVec3::ZERO,
        towards_eye: DVec3::new(0.5, -1.0, 0.9),
        distance: 60.0,
    },
    FlushPair {
        name: "half cylinder",
        flush: "difference() { cylinder(h = 10, r = 5); translate([0, 0, 5]) cylinder(h = 5, r = 5); }",
        clean: "cylinder(h = 5, r = 5);",
        centre: DVec3::new(0.0, 0.0, 5.0),
        towards_eye: DVec3::new(0.6, -1.0, 0.8),
        distance: 45.0,
    },
    FlushPair {
        name: "ball minus turned ball",
        flush: "difference() { sphere(5); rotate([0, 0, 30]) sphere(5); }",
        clean: "",
        centre: DVec3::ZERO,
        towards_eye: DVec3::new(0.6, -1.0, 0.8),
        distance: 40.0,
    },
    FlushPair {
        name: "ball minus ball turned about a skew axis",
        flush: "difference() { sphere(5); rotate([20, 30, 40]) sphere(5); }",
        clean: "",
        centre: DVec3::ZERO,
        towards_eye: DVec3::new(0.6, -1.0, 0.8),
        distance: 40.0,
    },
    FlushPair {
        name: "tube",
        flush: "difference() { cylinder(h = 10, r = 5); cylinder(h = 10, r = 3); }",
        clean: "difference() { cylinder(h = 10, r = 5); translate([0, 0, -1]) cylinder(h = 12, r = 3); }",
        centre: DVec3::new(0.0, 0.0, 5.0),
        towards_eye: DVec3::new(0.5, -1.0, 1.6),
        distance: 45.0,
    },
    FlushPair {
        name: "union with a flush top",
        flush: "union() { cube([10, 10, 10]); translate([5, 5, 4]) cube([10, 10, 6]); }",
        clean: "difference() {
            cube([15, 15, 10]);
            translate([10, -1, -1]) cube([6, 6, 12]);
            translate([-1, 10, -1]) cube([6, 6, 12]);
            translate([10, 4, -1]) cube([6, 12, 5]);
            translate([4, 10, -1]) cube([12, 6, 5]);
        }",
        centre: DVec3::new(7.5, 7.5, 5.0),
        towards_eye: DVec3::new(0.7, -1.0, 1.1),
        distance: 60.0,
    },
    // Each box's side slabs are the other's, written with other coefficients: a splat's clip
    // list must leave the other box's slab out (it would cut the splat at random where its
    // value on the shared face is rounding in f32).
    FlushPair {
        name: "intersection of boxes sharing their sides, turned",
        flush: "rotate([37, 37, 0]) intersection() { cube(10); translate([0, 0, 5]) cube(10); }",
        clean: "rotate([37, 37, 0]) translate([0, 0, 5]) cube([10, 10, 5]);",
        centre: DVec3::ZERO,
        towards_eye: DVec3::new(0.5, -1.0, 0.9),
        distance: 60.0,
    },
    FlushPair {
        name: "cylinder on a coaxial cylinder of its radius",
        flush: "union() { cylinder(h = 5, r = 4); translate([0, 0, 5]) cylinder(h = 5, r = 4); }",
        clean: "cylinder(h = 10, r = 4);",
        centre: DVec3::new(0.0, 0.0, 5.0),
        towards_eye: DVec3::new(0.6, -1.0, 0.8),
        distance: 45.0,
    },
];
