//! End-to-end tests of `qcsg render`: a PNG on success, exit codes, no file after a failure,
//! standard input and output, and the choice of renderer and device (`--renderer`, `--device`).
//! The splat cases need a GPU adapter; a software one (Mesa's lavapipe, which CI installs) is
//! enough, and without one they fail.

use std::path::PathBuf;

use qcsg_testkit::cli::{Invocation, Run};

const SCENE: &str =
    "difference() { cube(2, center = true); #sphere(1.3); }\n%translate([3, 0, 0]) sphere(1);\n";

fn qcsg(args: &[&str], stdin: &str) -> Run {
    Invocation::new(env!("CARGO_BIN_EXE_qcsg"))
        .args(args)
        .stdin(stdin)
        .run()
}

fn scratch_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("qcsg-render-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

#[test]
fn renders_a_png_and_says_how() {
    let dir = scratch_dir("ok");
    let out = dir.join("out.png");
    let run = qcsg(
        &[
            "render",
            "-",
            "-o",
            out.to_str().unwrap(),
            "--size",
            "40,30",
        ],
        SCENE,
    );
    assert_eq!(run.status, 0, "{}", run.stderr);
    let png = std::fs::read(&out).expect("the PNG");
    assert!(png.starts_with(b"\x89PNG"));
    // `auto` says which renderer it used: splats on a hardware GPU, else the CPU ray tracer.
    assert!(
        run.stderr.contains("with the CPU ray tracer (device: cpu")
            || run.stderr.contains("with the splat renderer (device: gpu"),
        "{}",
        run.stderr
    );
    // Quiet runs say nothing; the ray tracer's image does not depend on the thread count. (On
    // the CPU: probing GPU adapters may print to standard error from inside the driver, e.g.
    // Mesa's device-select layer without XDG_RUNTIME_DIR.)
    let traced = |name: &str, flags: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "render",
            "-",
            "-o",
            out.to_str().unwrap(),
            "--size",
            "40,30",
        ];
        args.extend(flags);
        args.extend(["--device", "cpu"]);
        let run = qcsg(&args, SCENE);
        (run, std::fs::read(&out).ok())
    };
    let (many, png) = traced("many.png", &[]);
    assert_eq!(many.status, 0, "{}", many.stderr);
    let (quiet, again) = traced("again.png", &["-q", "--threads", "1"]);
    assert_eq!(quiet.status, 0);
    assert!(quiet.stderr.is_empty(), "{}", quiet.stderr);
    assert_eq!(again, png);
    // Standard output.
    let piped = qcsg(
        &[
            "render", "-", "-o", "-", "--size", "40,30", "--camera", "front",
        ],
        SCENE,
    );
    assert_eq!(piped.status, 0, "{}", piped.stderr);
    assert!(piped.stdout.starts_with(b"\x89PNG"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The RGB pixels of a PNG.
fn pixels(png: &[u8]) -> Vec<[u8; 3]> {
    let image = image::load_from_memory(png).expect("a PNG").to_rgb8();
    image.pixels().map(|p| p.0).collect()
}

#[test]
fn renderer_and_device_choose_what_renders() {
    let dir = scratch_dir("choice");
    let render = |name: &str, flags: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "render",
            "-",
            "-o",
            out.to_str().unwrap(),
            "--size",
            "80,60",
        ];
        args.extend(flags);
        let run = qcsg(&args, SCENE);
        let png = std::fs::read(&out).ok();
        (run, png)
    };

    let (traced, reference) = render("cpu.png", &["--device", "cpu"]);
    assert_eq!(traced.status, 0, "{}", traced.stderr);
    assert!(
        traced
            .stderr
            .contains("with the CPU ray tracer (device: cpu")
    );
    let reference = pixels(&reference.expect("the ray-traced PNG"));

    // Splats on any adapter, and on a software one: the same picture up to silhouette pixels.
    for (name, flags, says) in [
        (
            "splat.png",
            &["--renderer", "splat"][..],
            "with the splat renderer",
        ),
        (
            "software.png",
            &["--renderer", "splat", "--device", "cpu"][..],
            "software)",
        ),
    ] {
        let (run, png) = render(name, flags);
        assert_eq!(run.status, 0, "{flags:?}: {}", run.stderr);
        assert!(run.stderr.contains(says), "{flags:?}: {}", run.stderr);
        let splats = pixels(&png.expect("the splat PNG"));
        assert_eq!(splats.len(), reference.len());
        let differing = splats
            .iter()
            .zip(&reference)
            .filter(|(a, b)| a != b)
            .count();
        assert!(
            differing * 20 < reference.len(),
            "{flags:?}: {differing} of {} pixels differ from the ray tracer's",
            reference.len()
        );
    }

    // `--device gpu` wants a hardware GPU: it renders splats or refuses, never falls back.
    let (run, png) = render("gpu.png", &["--device", "gpu"]);
    if run.status == 0 {
        assert!(run.stderr.contains("with the splat renderer (device: gpu"));
    } else {
        assert_eq!(run.status, 2, "{}", run.stderr);
        assert!(
            run.stderr.contains("no hardware GPU adapter"),
            "{}",
            run.stderr
        );
        assert!(png.is_none());
    }

    // The ray tracer does not run on a GPU.
    let (run, png) = render(
        "nonsense.png",
        &["--renderer", "raytrace", "--device", "gpu"],
    );
    assert_eq!(run.status, 2, "{}", run.stderr);
    assert!(run.stderr.contains("CPU only"), "{}", run.stderr);
    assert!(png.is_none());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn failures_leave_no_file() {
    let dir = scratch_dir("fail");
    let out = dir.join("out.png");
    let path = out.to_str().unwrap();
    let errors = qcsg(&["render", "-", "-o", path], "cube(;\n");
    assert_eq!(errors.status, 1);
    for bad in [
        vec!["render", "-", "-o", path, "--size", "0,10"],
        vec!["render", "-", "-o", path, "--camera", "1,1,1,1,1,1"],
        vec!["render", "-", "-o", path, "--camera", "sideways"],
        vec!["render", "no-such-file.qcsg", "-o", path],
    ] {
        let run = qcsg(&bad, SCENE);
        assert_eq!(run.status, 2, "{bad:?}: {}", run.stderr);
    }
    assert!(!out.exists());
    let unwritable = dir.join("missing-dir").join("out.png");
    let run = qcsg(
        &[
            "render",
            "-",
            "-o",
            unwritable.to_str().unwrap(),
            "--size",
            "8,6",
        ],
        SCENE,
    );
    assert_eq!(run.status, 2, "{}", run.stderr);
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    let _ = std::fs::remove_dir_all(&dir);
}
