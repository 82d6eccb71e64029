//! End-to-end tests of `qcsg sample`: the PLY read back (every point on its quadric, per the DNF
//! JSON of `qcsg compile`, and on the solid's surface), text and binary PLY agreeing, the stats
//! JSON, byte-identical output for any thread count, and the exit codes of docs/cli.md (bad radius:
//! usage error; errors in the program: 1), with no file left behind by a failed run.

use std::path::PathBuf;

use qcsg_testkit::cli::{Invocation, Run};
use serde_json::Value;

/// A cube of side 2 minus a sphere of radius 1.3: four quadrics, one term, feature curves.
const SCENE: &str = "difference() { cube(2, center = true); sphere(1.3); }\n";

fn qcsg(args: &[&str], stdin: &str) -> Run {
    Invocation::new(env!("CARGO_BIN_EXE_qcsg"))
        .args(args)
        .stdin(stdin)
        .run()
}

fn scratch_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("qcsg-sample-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

/// One vertex of the PLY.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Vertex {
    position: [f64; 3],
    normal: [f32; 3],
    radius: f32,
    quadric: u32,
    term: u32,
}

/// The PLY properties docs/cli.md specifies, in order.
const PROPERTIES: [&str; 9] = [
    "property double x",
    "property double y",
    "property double z",
    "property float nx",
    "property float ny",
    "property float nz",
    "property float radius",
    "property uint quadric",
    "property uint term",
];

/// Parses a PLY written by `qcsg sample` (binary little-endian or ASCII), checking its header.
fn read_ply(bytes: &[u8]) -> (String, Vec<Vertex>) {
    let end = b"end_header\n";
    let header_len = bytes
        .windows(end.len())
        .position(|w| w == end)
        .expect("end_header")
        + end.len();
    let header = std::str::from_utf8(&bytes[..header_len]).expect("text header");
    let lines: Vec<&str> = header.lines().collect();
    assert_eq!(lines[0], "ply");
    let format = lines[1]
        .strip_prefix("format ")
        .and_then(|f| f.strip_suffix(" 1.0"))
        .expect("format line")
        .to_string();
    let count: usize = lines
        .iter()
        .find_map(|l| l.strip_prefix("element vertex "))
        .expect("vertex element")
        .parse()
        .expect("vertex count");
    let properties: Vec<&str> = lines
        .iter()
        .copied()
        .filter(|l| l.starts_with("property"))
        .collect();
    assert_eq!(properties, PROPERTIES);
    let body = &bytes[header_len..];
    let vertices = match format.as_str() {
        "binary_little_endian" => {
            assert_eq!(body.len(), count * 48, "48 bytes per vertex");
            body.chunks_exact(48)
                .map(|v| {
                    let f64_at = |i: usize| f64::from_le_bytes(v[i..i + 8].try_into().unwrap());
                    let f32_at = |i: usize| f32::from_le_bytes(v[i..i + 4].try_into().unwrap());
                    let u32_at = |i: usize| u32::from_le_bytes(v[i..i + 4].try_into().unwrap());
                    Vertex {
                        position: [f64_at(0), f64_at(8), f64_at(16)],
                        normal: [f32_at(24), f32_at(28), f32_at(32)],
                        radius: f32_at(36),
                        quadric: u32_at(40),
                        term: u32_at(44),
                    }
                })
                .collect::<Vec<_>>()
        }
        "ascii" => {
            let text = std::str::from_utf8(body).expect("text body");
            text.lines()
                .map(|line| {
                    let f: Vec<&str> = line.split(' ').collect();
                    assert_eq!(f.len(), 9, "{line}");
                    Vertex {
                        position: [0, 1, 2].map(|i| f[i].parse().unwrap()),
                        normal: [3, 4, 5].map(|i| f[i].parse().unwrap()),
                        radius: f[6].parse().unwrap(),
                        quadric: f[7].parse().unwrap(),
                        term: f[8].parse().unwrap(),
                    }
                })
                .collect()
        }
        other => panic!("unexpected PLY format {other}"),
    };
    assert_eq!(vertices.len(), count);
    (format, vertices)
}

/// A quadric of the DNF JSON: `q(x) = xᵀ A x + 2 bᵀ x + c` at `x = p − origin`.
struct JsonQuadric {
    origin: [f64; 3],
    a: [[f64; 3]; 3],
    b: [f64; 3],
    c: f64,
}

impl JsonQuadric {
    fn from_json(value: &Value) -> Self {
        let numbers = |key: &str| -> Vec<f64> {
            value[key]
                .as_array()
                .expect(key)
                .iter()
                .map(|x| x.as_f64().expect("number"))
                .collect()
        };
        let o = numbers("origin");
        let k = numbers("coefficients");
        Self {
            origin: [o[0], o[1], o[2]],
            a: [[k[0], k[3], k[4]], [k[3], k[1], k[5]], [k[4], k[5], k[2]]],
            b: [k[6], k[7], k[8]],
            c: k[9],
        }
    }

    /// `|q(p)| / ‖∇q(p)‖`, the first-order distance of `p` to the surface.
    fn residual(&self, p: [f64; 3]) -> f64 {
        let x = [0, 1, 2].map(|i| p[i] - self.origin[i]);
        let ax = [0, 1, 2].map(|i| (0..3).map(|j| self.a[i][j] * x[j]).sum::<f64>());
        let value = (0..3)
            .map(|i| x[i] * ax[i] + 2.0 * self.b[i] * x[i])
            .sum::<f64>()
            + self.c;
        let gradient = [0, 1, 2].map(|i| 2.0 * (ax[i] + self.b[i]));
        value.abs() / gradient.iter().map(|g| g * g).sum::<f64>().sqrt()
    }
}

fn dnf_quadrics(program: &str) -> Vec<JsonQuadric> {
    let run = qcsg(
        &["compile", "-", "--emit", "dnf", "--format", "json"],
        program,
    );
    assert_eq!(run.status, 0, "{}", run.stderr);
    let dnf: Value = serde_json::from_slice(&run.stdout).expect("DNF JSON");
    dnf["quadrics"]
        .as_array()
        .expect("quadrics")
        .iter()
        .map(JsonQuadric::from_json)
        .collect()
}

fn stats_of(text: &str) -> Value {
    serde_json::from_str(text.trim()).expect("stats JSON")
}

#[test]
fn binary_ply_points_are_on_the_surface() {
    let dir = scratch_dir("binary");
    let out = dir.join("out.ply");
    let run = qcsg(
        &[
            "sample",
            "-",
            "--radius",
            "0.2",
            "-o",
            out.to_str().unwrap(),
            "--stats",
        ],
        SCENE,
    );
    assert_eq!(run.status, 0, "{}", run.stderr);
    let stats = stats_of(std::str::from_utf8(&run.stdout).expect("text"));
    let (format, vertices) = read_ply(&std::fs::read(&out).expect("the PLY"));
    assert_eq!(format, "binary_little_endian");
    assert_eq!(stats["samples"].as_u64(), Some(vertices.len() as u64));
    assert!(vertices.len() > 100, "{} samples", vertices.len());

    let quadrics = dnf_quadrics(SCENE);
    assert_eq!(stats["quadrics"].as_u64(), Some(quadrics.len() as u64));
    let diagonal = 12f64.sqrt();
    let mut on_each = vec![0usize; quadrics.len()];
    for v in &vertices {
        let p = v.position;
        let q = &quadrics[v.quadric as usize];
        assert!(
            q.residual(p) <= 1e-9 * diagonal,
            "{v:?} is {:e} off its quadric",
            q.residual(p)
        );
        assert_eq!(v.term, 0);
        on_each[v.quadric as usize] += 1;
        // On the solid's surface: inside the closed cube and outside the open ball.
        let tol = 1e-9;
        assert!(
            p.iter().all(|c| c.abs() <= 1.0 + tol),
            "{v:?} outside the cube"
        );
        let length = p.iter().map(|c| c * c).sum::<f64>().sqrt();
        assert!(length >= 1.3 - tol, "{v:?} inside the removed sphere");
        let n = v.normal.iter().map(|c| c * c).sum::<f32>().sqrt();
        assert!((n - 1.0).abs() < 1e-5, "{v:?}: normal");
        assert!(v.radius > 0.0 && v.radius <= 0.2, "{v:?}: radius");
    }
    // Every face of the cube and the spherical cavity get samples.
    assert!(on_each.iter().all(|&n| n > 0), "{on_each:?}");
    assert!(run.stderr.contains("sampled"), "{}", run.stderr);
}

#[test]
fn ascii_and_binary_ply_agree() {
    let dir = scratch_dir("ascii");
    let (binary, ascii) = (dir.join("b.ply"), dir.join("a.ply"));
    for (path, extra) in [(&binary, None), (&ascii, Some("--ascii"))] {
        let mut args = vec!["sample", "-", "--radius", "4%", "-q", "-o"];
        args.push(path.to_str().unwrap());
        args.extend(extra);
        let run = qcsg(&args, SCENE);
        assert_eq!(run.status, 0, "{}", run.stderr);
        assert!(run.stderr.is_empty(), "quiet: {}", run.stderr);
    }
    let (bf, b) = read_ply(&std::fs::read(&binary).expect("binary PLY"));
    let (af, a) = read_ply(&std::fs::read(&ascii).expect("ASCII PLY"));
    assert_eq!(
        (bf.as_str(), af.as_str()),
        ("binary_little_endian", "ascii")
    );
    assert_eq!(a, b, "positions round-trip exactly through the text form");
}

#[test]
fn stats_json_has_the_documented_keys() {
    let dir = scratch_dir("stats");
    let stats_file = dir.join("stats.json");
    let run = qcsg(
        &[
            "sample",
            "-",
            "--radius",
            "5%",
            "--stats",
            stats_file.to_str().unwrap(),
            "--threads",
            "2",
        ],
        SCENE,
    );
    assert_eq!(run.status, 0, "{}", run.stderr);
    assert!(run.stdout.is_empty(), "nothing on stdout without -o -");
    let stats = stats_of(&std::fs::read_to_string(&stats_file).expect("stats file"));
    for key in [
        "samples",
        "distance_queries",
        "seconds",
        "threads",
        "radius",
        "quadrics",
        "terms",
        "clip_indices",
    ] {
        assert!(
            stats.get(key).is_some_and(Value::is_number),
            "{key}: {stats}"
        );
    }
    assert_eq!(stats["threads"].as_u64(), Some(2));
    assert_eq!(stats["quadrics"].as_u64(), Some(4));
    assert_eq!(stats["terms"].as_u64(), Some(1));
    // `5%` is a fraction of the bounding-box diagonal (the cube's, 2√3).
    let radius = stats["radius"].as_f64().expect("radius");
    assert!((radius - 0.05 * 12f64.sqrt()).abs() < 1e-12, "{radius}");
    assert!(stats["distance_queries"].as_u64() > stats["samples"].as_u64());

    // With the PLY on standard output, the stats go to standard error.
    let run = qcsg(
        &["sample", "-", "--radius", "5%", "-o", "-", "--stats", "-q"],
        SCENE,
    );
    assert_eq!(run.status, 0, "{}", run.stderr);
    let (_, vertices) = read_ply(&run.stdout);
    let stats = stats_of(&run.stderr);
    assert_eq!(stats["samples"].as_u64(), Some(vertices.len() as u64));
}

#[test]
fn output_is_identical_for_any_thread_count() {
    let scene = "union() { difference() { cube(2, center = true); sphere(1.3); } \
                 translate([1, 1, 1]) cylinder(h = 2, r = 0.4, center = true); }\n";
    let ply = |threads: &str| {
        let run = qcsg(
            &[
                "sample",
                "-",
                "--radius",
                "3%",
                "-o",
                "-",
                "-q",
                "--threads",
                threads,
            ],
            scene,
        );
        assert_eq!(run.status, 0, "{}", run.stderr);
        run.stdout
    };
    let one = ply("1");
    assert!(one.len() > 48 * 1000, "{} bytes", one.len());
    assert!(one == ply("2"), "1 and 2 threads give different PLY files");
}

#[test]
fn a_bad_radius_is_a_usage_error() {
    let dir = scratch_dir("radius");
    let out = dir.join("out.ply");
    for bad in ["0", "-1", "abc", "0%", "nan", "inf", "1%%"] {
        let run = qcsg(
            &["sample", "-", "--radius", bad, "-o", out.to_str().unwrap()],
            SCENE,
        );
        assert_eq!(run.status, 2, "--radius {bad}: {}", run.stderr);
        assert!(run.stderr.contains("radius"), "{}", run.stderr);
        assert!(!out.exists(), "--radius {bad} wrote a file");
    }
    let missing = qcsg(&["sample", "-"], SCENE);
    assert_eq!(missing.status, 2, "{}", missing.stderr);
}

#[test]
fn an_unbounded_solid_is_an_input_error() {
    let run = qcsg(
        &["sample", "-", "--radius", "1%"],
        "quadric([0, 0, 0, 0, 0, 0, 0, 0, 1, 0]);\n",
    );
    assert_eq!(run.status, 1, "{}", run.stderr);
    assert!(run.stderr.contains("unbounded"), "{}", run.stderr);
}

#[test]
fn errors_in_the_program_exit_1_without_output() {
    let dir = scratch_dir("errors");
    let out = dir.join("out.ply");
    let stats = dir.join("stats.json");
    for program in ["cube(\n", "sphere(r = undefined_name);\n"] {
        let run = qcsg(
            &[
                "sample",
                "-",
                "--radius",
                "0.1",
                "-o",
                out.to_str().unwrap(),
                "--stats",
                stats.to_str().unwrap(),
            ],
            program,
        );
        assert_eq!(run.status, 1, "{program}: {}", run.stderr);
        assert!(run.stderr.contains("error"), "{}", run.stderr);
        assert!(
            !out.exists() && !stats.exists(),
            "{program}: a file was written"
        );
    }
    // As JSON diagnostics on standard output.
    let run = qcsg(
        &["sample", "-", "--radius", "0.1", "--format", "json"],
        "cube(\n",
    );
    assert_eq!(run.status, 1);
    let diagnostics: Value = serde_json::from_slice(&run.stdout).expect("diagnostics JSON");
    assert_eq!(diagnostics[0]["severity"], "error");
}

#[test]
fn unwritable_output_is_a_usage_error_and_leaves_nothing() {
    let dir = scratch_dir("unwritable");
    let out = dir.join("missing-directory").join("out.ply");
    let run = qcsg(
        &[
            "sample",
            "-",
            "--radius",
            "10%",
            "-o",
            out.to_str().unwrap(),
        ],
        SCENE,
    );
    assert_eq!(run.status, 2, "{}", run.stderr);
    assert!(run.stderr.contains("cannot write"), "{}", run.stderr);
    assert!(std::fs::read_dir(&dir).expect("dir").next().is_none());
}

/// Rectangles given up unproven are announced on standard error, exactly when the stats count
/// any: a hyperboloid of two sheets whose vertices nearly touch has them, the cube minus a ball
/// has none.
#[test]
fn unproven_rectangles_are_a_warning() {
    let gap = "intersection() {\n\
               hyperboloid(h = 2, r = 1, c = 1e-6, sheets = 2, center = true);\n\
               sphere(1);\n\
               }\n";
    for (name, program) in [("gap", gap), ("cube", SCENE)] {
        let run = qcsg(&["sample", "-", "--radius", "10%", "--stats", "-"], program);
        assert_eq!(run.status, 0, "{name}: {}", run.stderr);
        let stats: Value = serde_json::from_slice(&run.stdout).expect("stats JSON");
        let unresolved = stats["unresolved"].as_u64().expect("unresolved count");
        let warned = run.stderr.contains("given up unproven");
        assert_eq!(warned, unresolved > 0, "{name}: {}", run.stderr);
    }
}

/// A crossed sampling limit is an input error at the quadric being sampled, naming the flag
/// that raises it, with no file written: too many samples for a tiny radius (E0604), distances
/// of many overlapping parts that hold more memory than the sample limit implies (E0604 too),
/// too many distance queries for surfaces that nearly coincide (E0605). The same runs pass with
/// the limit raised.
#[test]
fn crossed_sampling_limits_are_errors_at_a_span() {
    let dir = scratch_dir("limits");
    let out = dir.join("out.ply");
    // A shell 1e-9 thick, cut open by a half-space: the cut face is a ring 1e-9 wide, which no
    // corner bound can tell from its rims.
    let nested =
        "difference() {\n  sphere(1 + 1e-9);\n  sphere(1);\n  halfspace([0, 0, -1], -0.3);\n}\n";
    // 60 parts that all overlap, each a ball cut by a turned cube (7 literals): each one's
    // distance holds the other 59 (about 250,000 samples' worth in all), four times what their
    // regions take (10 samples' worth each), while the samples number a few thousand. Past a
    // limit of 50,000 the distances hold most of what is charged, however the threads share
    // the parts out.
    let balls = (0..60)
        .map(|i| {
            format!(
                "rotate([0, 0, {}]) translate([1, 0, 0]) intersection() {{ sphere(3); \
                 rotate([{}, {}, 0]) cube(4.6, center = true); }}\n",
                6 * i,
                7 * i,
                11 * i
            )
        })
        .collect::<String>();
    let balls = format!("union() {{\n{balls}}}\n");
    let cases = [
        (SCENE, "--max-samples", "100", "1000000", "E0604", "samples"),
        (
            &balls,
            "--max-samples",
            "50000",
            "1000000",
            "E0604",
            "distances set up",
        ),
        (
            nested,
            "--max-queries",
            "10000",
            "100000000",
            "E0605",
            "queries",
        ),
    ];
    let out_path = out.to_str().unwrap();
    for (program, flag, low, high, code, what) in cases {
        let run_with = |limit: &str| {
            let args = [
                "sample", "-", "--radius", "10%", "-o", out_path, flag, limit,
            ];
            qcsg(&[&args[..], &["--format", "json"]].concat(), program)
        };
        let run = run_with(low);
        assert_eq!(run.status, 1, "{code}: {}", run.stderr);
        assert!(!out.exists(), "{code}: a file was written");
        let diagnostics: Value = serde_json::from_slice(&run.stdout).expect("diagnostics JSON");
        let error = &diagnostics[0];
        assert_eq!(error["code"], code);
        assert!(error["message"].as_str().unwrap().contains(what), "{error}");
        assert!(error["help"].as_str().unwrap().contains(flag), "{error}");
        let span = error["byte_range"].as_array().expect("a span");
        let (start, end) = (span[0].as_u64().unwrap(), span[1].as_u64().unwrap());
        assert!(start < end, "{error}");
        let run = run_with(high);
        assert_eq!(run.status, 0, "{code} raised: {}", run.stderr);
        assert!(out.exists());
        std::fs::remove_file(&out).expect("remove");
    }
}
