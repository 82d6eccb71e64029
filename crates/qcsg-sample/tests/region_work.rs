//! The region partition's work follows the surface's area over the radius squared, not the
//! scale of its own features, and the memory of a run stays within what its sample limit
//! implies. Four scenes the fuzzing harness found (`docs/fuzzing.md`, failures 2, 3 and 5):
//! - a paraboloid `1.2·10⁸` long and `74` wide at 5 % of its diagonal: the partition cut its
//!   rim into squares of its width (2.4 million regions, half a million samples, 7 s);
//! - a flat hyperboloid, whose waist turns within `10⁻³` around a circle `1,400` long, beside
//!   a cube, at 5 %: 1.6 million regions, each refined to the scale of the waist (2 s, 1.2 GB);
//! - an ellipsoid with semi-axes `[1, 1, 10⁶]` turned off the axes and cut by a ball, at
//!   0.01 % with a limit of 200,000 samples: 1.7 GB held before the limit stopped it;
//! - an elliptic cone `10⁴` times wider than thick, a blade, at 5 %: its thin edges were
//!   refined to the scale at which they turn (1.7 million regions, 6 s).
//!
//! Each runs on a thread of its own under a watchdog: past [`TIME_CAP`] the test fails instead
//! of hanging, and past [`heap::HEAP_CAP`] of heap (counted by `peak_alloc`) the process aborts
//! instead of exhausting the machine. The bounds asserted are counts of work (regions,
//! rectangles, samples) and the heap's peak, which do not depend on the machine's speed.

mod common;

use std::sync::mpsc;
use std::time::Duration;

use common::{compile_text, diagonal, heap};
use peak_alloc::PeakAlloc;
use qcsg_sample::{SampleError, SampleLimits, Sampling, sample_with_limits};

#[global_allocator]
static HEAP: PeakAlloc = PeakAlloc;

/// The longest one scene may take, in a debug build on a loaded machine: the old partition
/// took seconds in a release build, minutes in a debug one.
const TIME_CAP: Duration = Duration::from_secs(120);

/// Samples `text` at `relative` of its diagonal under `limits` on a thread of its own, with the
/// heap's peak during the run; fails past [`TIME_CAP`].
fn sample_text(
    text: &'static str,
    relative: f64,
    limits: SampleLimits,
) -> (Result<Sampling, SampleError>, usize) {
    heap::watch(&HEAP);
    let _one = heap::measuring();
    let dnf = compile_text("work.qcsg", text.to_owned()).expect("compiles");
    let radius = relative * diagonal(&dnf);
    heap::peak_of(&HEAP, || {
        let (done, result) = mpsc::channel();
        std::thread::spawn(move || {
            let progress = |_| {};
            let _ = done.send(sample_with_limits(&dnf, radius, limits, &progress));
        });
        result
            .recv_timeout(TIME_CAP)
            .unwrap_or_else(|_| panic!("{text}: no result within {TIME_CAP:?}"))
    })
}

/// Samples `text` at `relative` of its diagonal and checks the work against `most` and the
/// heap against `heap_mb`.
fn check(text: &'static str, relative: f64, most: u64, heap_mb: usize) {
    let (sampled, peak) = sample_text(text, relative, SampleLimits::default());
    let stats = sampled.expect("samples").stats;
    eprintln!("{text}: {stats:?}, {} MB", peak >> 20);
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
    assert!(peak < heap_mb << 20, "{text}: {} MB held", peak >> 20);
}

#[test]
fn a_needle_paraboloid_costs_what_its_area_needs() {
    check("paraboloid(3.2 ^ 16, 37);", 0.05, 2_000, 100);
}

#[test]
fn a_flat_hyperboloid_costs_what_its_area_needs() {
    let text = "cube(32.35, false); hyperboloid(h = 7.62, r = 226.45, center = false);";
    check(text, 0.05, 2_000, 100);
}

/// Cones kept no small patch (for their apex): the thin edges of this blade took 1.7 million
/// regions at 5 %; with small patches kept but refined wherever the cap crosses one, 3.4
/// million and 3.2 GB.
#[test]
fn a_flat_elliptic_cone_costs_what_its_area_needs() {
    check("cone(18, [0.001, 10.67]);", 0.05, 2_000, 100);
}

#[test]
fn a_needle_ellipsoid_stays_within_its_sample_limit() {
    let text = "intersection() { rotate([30, 40, 50]) ellipsoid([1, 1, 1e6]); sphere(1e6); }";
    let limits = SampleLimits {
        max_samples: 200_000,
        ..SampleLimits::default()
    };
    let (sampled, peak) = sample_text(text, 1e-4, limits);
    match &sampled {
        Ok(sampling) => {
            assert!(sampling.stats.samples <= limits.max_samples);
            assert!(
                sampling.stats.basic_regions <= 1_000,
                "{:?}",
                sampling.stats
            );
        }
        Err(SampleError::TooManySamples { .. }) => {}
        Err(other) => panic!("{other}"),
    }
    // 200,000 samples of 72 bytes, their index and clip lists: far below this.
    assert!(peak < 200 << 20, "{} MB held", peak >> 20);
}
