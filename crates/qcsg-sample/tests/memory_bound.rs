//! A radius far below the scene's size is refused before the sampler allocates: the fewest
//! samples the regions can hold are known up front, and a run past the sample limit stops with
//! [`SampleError::TooManySamples`] instead of filling memory first (`examples/rocket.qcsg` at
//! `1e-9` had reached 2.7 GB before it stopped). Radii that are no numbers, not positive or
//! past any scale give an error or a plain run, never a panic or a hang.
//!
//! This test binary counts its heap (`peak_alloc`), and a watchdog aborts it once the heap
//! passes [`heap::HEAP_CAP`]: a sampler that regressed to filling memory fails the test instead of
//! exhausting the machine.

mod common;

use common::{Rng, compile_file, compile_text, heap, workspace_root};
use peak_alloc::PeakAlloc;
use qcsg_sample::{DEFAULT_MAX_SAMPLES, SampleError, SampleLimits, sample, sample_with_limits};

#[global_allocator]
static HEAP: PeakAlloc = PeakAlloc;

/// The most heap held at once while `run` runs, beyond what was held before, one test at a
/// time, under the heap's watchdog.
fn peak_during<T>(run: impl FnOnce() -> T) -> (T, usize) {
    heap::watch(&HEAP);
    let _one = heap::measuring();
    heap::peak_of(&HEAP, run)
}

fn rocket() -> qcsg_csg::Dnf {
    compile_file(&workspace_root().join("examples/rocket.qcsg")).expect("rocket compiles")
}

#[test]
fn a_radius_far_below_the_scene_is_refused_before_sampling() {
    let dnf = rocket();
    // Bodies of about 60 units: `1e-9` asks for about 10²¹ samples.
    let (sampled, peak) = peak_during(|| sample(&dnf, 1e-9));
    match sampled {
        Err(SampleError::TooManySamples { limit, .. }) => assert_eq!(limit, DEFAULT_MAX_SAMPLES),
        other => panic!("expected the sample limit, got {other:?}"),
    }
    assert!(peak < 300 << 20, "{} MB held at once", peak >> 20);
}

#[test]
fn radii_below_floating_point_resolution_are_refused_too() {
    let dnf = rocket();
    for radius in [1e-30, 1e-300, f64::MIN_POSITIVE, 5e-324] {
        let (sampled, peak) = peak_during(|| sample(&dnf, radius));
        assert!(
            matches!(sampled, Err(SampleError::TooManySamples { .. })),
            "{radius}: {sampled:?}"
        );
        assert!(peak < 300 << 20, "{radius}: {} MB", peak >> 20);
    }
}

#[test]
fn a_radius_that_is_not_a_positive_number_is_an_error() {
    let dnf = rocket();
    for radius in [0.0, -0.0, -1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let sampled = sample(&dnf, radius);
        assert!(
            matches!(sampled, Err(SampleError::InvalidRadius(_))),
            "{radius}: {sampled:?}"
        );
    }
}

#[test]
fn a_radius_far_above_the_scene_samples_each_part_once() {
    let dnf = rocket();
    for radius in [1e6, 1e300, f64::MAX] {
        let sampling = sample(&dnf, radius).expect("samples");
        assert!(!sampling.samples.is_empty(), "{radius}");
        assert!(sampling.samples.len() < 10_000, "{radius}");
    }
}

#[test]
fn the_limit_stops_a_run_that_the_bound_lets_through() {
    // At 1 % of the diagonal the rocket takes about 14 M samples, and the bound up front is
    // below 1 M: a limit of 1 M stops the run while it samples, within the memory it implies.
    let dnf = rocket();
    let limits = SampleLimits {
        max_samples: 1_000_000,
        ..SampleLimits::default()
    };
    let (sampled, peak) = peak_during(|| sample_with_limits(&dnf, 0.01, limits, &|_| {}));
    assert!(
        matches!(
            sampled,
            Err(SampleError::TooManySamples {
                limit: 1_000_000,
                ..
            })
        ),
        "{sampled:?}"
    );
    // A million samples of 72 bytes, or deferred rectangles of 112, and buffers that double.
    assert!(peak < 400 << 20, "{} MB held at once", peak >> 20);
}

#[test]
fn distances_of_many_overlapping_parts_are_charged_to_the_limit() {
    // 1,500 balls that all overlap: each ball's eq. 22 holds the other 1,499, about 600 MB in
    // all (3,000 such balls took 4.2 GB and 45 s at 5 % of the diagonal). The distances count
    // against the sample limit as the samples that take as much memory, so a limit of 200,000
    // samples (14 MB) stops the set-up early, within the memory it implies.
    let mut rng = Rng::new(7);
    let mut text = String::from("union() {\n");
    for _ in 0..1500 {
        let [x, y, z] = [0; 3].map(|_| 4.0 * rng.unit());
        text += &format!("translate([{x}, {y}, {z}]) sphere(3);\n");
    }
    text += "}\n";
    let dnf = compile_text("balls.scad", text).expect("balls compile");
    let limits = SampleLimits {
        max_samples: 200_000,
        ..SampleLimits::default()
    };
    let (sampled, peak) = peak_during(|| sample_with_limits(&dnf, 0.5, limits, &|_| {}));
    assert!(
        matches!(
            sampled,
            Err(SampleError::DistancesTooLarge { limit: 200_000, .. })
        ),
        "{sampled:?}"
    );
    assert!(peak < 100 << 20, "{} MB held at once", peak >> 20);
}
