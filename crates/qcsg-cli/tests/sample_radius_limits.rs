//! `qcsg sample` at radii no run could honour: far below the scene's size it refuses with the
//! sample limit's diagnostic (E0604) before it allocates the samples (the rocket at `1e-9` had
//! taken 9 s and 2.7 GB to get there), and a percentage that comes to no length is a usage
//! error. Each run has an address space of 1 GiB (`ulimit -v`): a sampler that regressed to
//! filling memory first fails the test instead of exhausting the machine.

#![cfg(unix)]

use std::path::PathBuf;
use std::time::Duration;

use qcsg_testkit::cli::{Invocation, Run};
use serde_json::Value;

/// The address space each run may take, in KiB.
const ADDRESS_SPACE_KIB: u64 = 1 << 20;

/// Far above the milliseconds a refusal takes, far below the minutes an attempt would.
const GENEROUS: Duration = Duration::from_secs(20);

/// `qcsg` with `args` (from the workspace root), in an address space of
/// [`ADDRESS_SPACE_KIB`], with `stdin` as its standard input.
fn qcsg_limited(args: &[&str], stdin: &str) -> Run {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    Invocation::with_address_space(env!("CARGO_BIN_EXE_qcsg"), ADDRESS_SPACE_KIB)
        .args(args)
        .current_dir(root)
        .stdin(stdin)
        .run()
}

#[test]
fn a_radius_far_below_the_scene_is_refused_before_sampling() {
    for radius in ["1e-9", "1e-9%", "1e-30", "1e-300", "5e-324"] {
        let args = [
            "sample",
            "examples/rocket.qcsg",
            "--radius",
            radius,
            "--format",
            "json",
        ];
        let run = qcsg_limited(&args, "");
        assert_eq!(run.status, 1, "--radius {radius}: {}", run.stderr);
        let diagnostics: Value = serde_json::from_slice(&run.stdout).expect("diagnostics JSON");
        let error = &diagnostics[0];
        assert_eq!(error["code"], "E0604", "--radius {radius}: {error}");
        assert!(
            error["help"].as_str().unwrap().contains("--max-samples"),
            "{error}"
        );
        let span = error["byte_range"].as_array().expect("a span");
        assert!(span[0].as_u64() < span[1].as_u64(), "{error}");
        assert!(run.took < GENEROUS, "--radius {radius}: {:?}", run.took);
    }
}

#[test]
fn a_percentage_that_comes_to_no_length_is_a_usage_error() {
    // `1e-323 %` of the diagonal rounds to zero, `1e308 %` of a diagonal of 3,464 to infinity.
    for (radius, program) in [("1e-323%", "sphere(1);\n"), ("1e308%", "sphere(1e3);\n")] {
        let run = qcsg_limited(&["sample", "-", "--radius", radius], program);
        assert_eq!(run.status, 2, "--radius {radius}: {}", run.stderr);
        assert!(
            run.stderr.contains("not a positive finite length"),
            "--radius {radius}: {}",
            run.stderr
        );
    }
}

#[test]
fn radii_that_are_no_positive_numbers_are_usage_errors() {
    for radius in [
        "0", "-0", "-1e-9", "NaN", "inf", "-inf", "1e999", "0%", "-1%", "nan%",
    ] {
        // `--radius=-0`: as a separate argument a leading `-` would read as a flag.
        let flag = format!("--radius={radius}");
        let run = qcsg_limited(&["sample", "-", &flag], "sphere(1);\n");
        assert_eq!(run.status, 2, "{flag}: {}", run.stderr);
        assert!(run.stderr.contains("radius"), "{flag}: {}", run.stderr);
    }
}

#[test]
fn a_radius_far_above_the_scene_samples_it() {
    let run = qcsg_limited(
        &["sample", "-", "--radius", "1e300", "--stats", "-", "-q"],
        "sphere(1);\n",
    );
    assert_eq!(run.status, 0, "{}", run.stderr);
    let stats: Value = serde_json::from_slice(&run.stdout).expect("stats JSON");
    let samples = stats["samples"].as_u64().expect("a count");
    assert!((1..100).contains(&samples), "{stats}");
}
