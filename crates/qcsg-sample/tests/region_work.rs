//! The region partition's work follows the surface's area over the radius squared, not the
//! length of a heightfield's rim over its own fine scale: a paraboloid `1.2·10⁸` long and `74`
//! wide, and a flat hyperboloid `7.62` high flaring to `1,800` across beside a cube, each at 5 %
//! of the diagonal, where a few hundred samples cover them. Before, the partition cut the
//! rectangles along the rim into squares of the sheet's width (the longer edge first) and kept
//! refining them below the radius: 2.4 million basic regions and half a million samples for the
//! paraboloid (6 s), 1.5 million regions for the hyperboloid, both stopped only by the
//! partition's own rectangle budget.

mod common;

use common::{compile_text, diagonal};
use qcsg_sample::sample;

/// Samples `text` at `relative` of its diagonal and checks the work against `most`.
fn check(text: &str, relative: f64, most: u64) {
    let dnf = compile_text("work.qcsg", text.to_owned()).expect("compiles");
    let sampling = sample(&dnf, relative * diagonal(&dnf)).expect("samples");
    let stats = sampling.stats;
    eprintln!("{text}: {stats:?}");
    assert!(
        stats.basic_regions <= most,
        "{text}: {} basic regions",
        stats.basic_regions
    );
    assert!(
        stats.regions.examined <= 4 * most,
        "{text}: {} rectangles examined",
        stats.regions.examined
    );
    assert!(stats.samples <= most, "{text}: {} samples", stats.samples);
}

#[test]
fn a_needle_paraboloid_costs_what_its_area_needs() {
    check("paraboloid(3.2 ^ 16, 37);", 0.05, 2_000);
}

#[test]
fn a_flat_hyperboloid_costs_what_its_area_needs() {
    let text = "cube(32.35, false); hyperboloid(h = 7.62, r = 226.45, center = false);";
    check(text, 0.05, 2_000);
}
