//! The examples gallery (`examples/`): every example checks clean, its committed preview
//! (`examples/previews/NAME.png`) is what `qcsg render` makes of it today, and the gallery page
//! (`examples/README.md`) shows every example with the command that renders its preview; the
//! examples are formatted by `qcsg fmt`.
//!
//! An example keeps its preview settings in a header line, `// preview: --camera iso --size
//! 480,360` (any `qcsg render` flags), and may name the warnings it shows on purpose in another,
//! `// warnings: W0106` (for example a `%` part, which is never part of the solid). Previews are
//! always made with the exact CPU ray tracer. After an intended change,
//! `QCSG_BLESS=1 cargo test -p qcsg-cli --test gallery` renders every preview again.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use qcsg_testkit::cli::Invocation;

/// The largest mean absolute difference per channel, in 8-bit steps.
const MAX_MEAN_DIFFERENCE: f64 = 0.5;
/// A pixel differs visibly when a channel is off by more than this.
const VISIBLE_DIFFERENCE: u8 = 24;
/// The largest share of visibly different pixels: a few silhouette pixels may flip with the last
/// bits of floating point on another machine, a moved or resized feature changes many more.
const MAX_DIFFERENT_SHARE: f64 = 0.0005;
/// Flags every preview is rendered with: the reference renderer, whatever the default becomes.
const REFERENCE_RENDERER: [&str; 2] = ["--renderer", "raytrace"];

/// One example scene and the settings from its header.
struct Example {
    /// The file name without its extension, also the preview's name.
    name: String,
    /// The file name with its extension (`wheel.qcsg`).
    file_name: String,
    path: PathBuf,
    /// The `qcsg render` flags of its preview.
    preview_args: Vec<String>,
    /// Warning codes it shows on purpose.
    expected_warnings: BTreeSet<String>,
}

impl Example {
    /// The command that renders the preview, as the gallery page shows it.
    fn render_command(&self) -> String {
        let mut words = vec![
            "qcsg".to_owned(),
            "render".to_owned(),
            format!("examples/{}", self.file_name),
            "-o".to_owned(),
            format!("{}.png", self.name),
        ];
        words.extend(REFERENCE_RENDERER.iter().map(|s| (*s).to_owned()));
        words.extend(self.preview_args.iter().cloned());
        words.join(" ")
    }

    fn preview_path(&self) -> PathBuf {
        previews_dir().join(format!("{}.png", self.name))
    }
}

fn examples_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

fn previews_dir() -> PathBuf {
    examples_dir().join("previews")
}

fn blessing() -> bool {
    std::env::var_os("QCSG_BLESS").is_some_and(|v| v == "1")
}

/// The value of a `// key: value` header line, if the file has one.
fn header_value<'a>(text: &'a str, key: &str) -> Option<&'a str> {
    text.lines()
        .filter_map(|line| line.trim().strip_prefix("//"))
        .find_map(|comment| comment.trim().strip_prefix(key)?.strip_prefix(':'))
        .map(str::trim)
}

/// Every `.qcsg` and `.scad` file directly in `examples/`, sorted by name.
fn examples() -> Vec<Example> {
    let mut found = Vec::new();
    for entry in std::fs::read_dir(examples_dir()).expect("examples/ is readable") {
        let path = entry.expect("a directory entry").path();
        let extension = path.extension().and_then(|e| e.to_str());
        if !matches!(extension, Some("qcsg" | "scad")) {
            continue;
        }
        let file_name = path.file_name().unwrap().to_string_lossy().into_owned();
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let text = std::fs::read_to_string(&path).expect("an example is readable");
        let preview = header_value(&text, "preview").unwrap_or_else(|| {
            panic!("{file_name}: no `// preview: <qcsg render flags>` header line")
        });
        let expected_warnings = header_value(&text, "warnings")
            .map(|codes| {
                codes
                    .split(|c: char| c == ',' || c.is_whitespace())
                    .take_while(|word| !word.starts_with('('))
                    .filter(|word| !word.is_empty())
                    .map(str::to_owned)
                    .collect()
            })
            .unwrap_or_default();
        found.push(Example {
            name,
            file_name,
            path,
            preview_args: preview.split_whitespace().map(str::to_owned).collect(),
            expected_warnings,
        });
    }
    found.sort_by(|a, b| a.name.cmp(&b.name));
    found
}

/// A scratch directory for this test process.
fn scratch_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("qcsg-gallery-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

/// A run of the built `qcsg`.
fn qcsg() -> Invocation {
    Invocation::new(env!("CARGO_BIN_EXE_qcsg"))
}

/// Renders the example's preview into `out` with the built `qcsg`; the error is its stderr.
fn render(example: &Example, out: &Path) -> Result<(), String> {
    let run = qcsg()
        .arg("render")
        .arg(&example.path)
        .arg("-o")
        .arg(out)
        .args(REFERENCE_RENDERER)
        .args(&example.preview_args)
        .arg("-q")
        .run();
    if run.status == 0 {
        Ok(())
    } else {
        Err(run.stderr)
    }
}

/// How far apart two images are.
#[derive(Debug)]
struct Difference {
    mean: f64,
    visible_pixels: usize,
    share: f64,
}

impl Difference {
    fn within_tolerance(&self) -> bool {
        self.mean <= MAX_MEAN_DIFFERENCE && self.share <= MAX_DIFFERENT_SHARE
    }
}

/// The difference between two PNG files of the same size; `Err` when one cannot be read or the
/// sizes differ.
fn compare(new: &Path, old: &Path) -> Result<Difference, String> {
    let load = |path: &Path| {
        image::open(path)
            .map(|image| image.to_rgb8())
            .map_err(|e| format!("cannot read {}: {e}", path.display()))
    };
    let (new, old) = (load(new)?, load(old)?);
    if new.dimensions() != old.dimensions() {
        return Err(format!(
            "the size changed from {:?} to {:?}",
            old.dimensions(),
            new.dimensions()
        ));
    }
    let mut total = 0u64;
    let mut visible_pixels = 0usize;
    for (a, b) in new.pixels().zip(old.pixels()) {
        let worst = a.0.iter().zip(b.0).map(|(x, y)| x.abs_diff(y)).max();
        total +=
            a.0.iter()
                .zip(b.0)
                .map(|(x, y)| u64::from(x.abs_diff(y)))
                .sum::<u64>();
        if worst.is_some_and(|d| d > VISIBLE_DIFFERENCE) {
            visible_pixels += 1;
        }
    }
    let pixels = f64::from(new.width()) * f64::from(new.height());
    Ok(Difference {
        mean: total as f64 / (3.0 * pixels),
        visible_pixels,
        share: visible_pixels as f64 / pixels,
    })
}

#[test]
fn the_gallery_has_at_least_fifteen_examples() {
    let count = examples().len();
    assert!(
        count >= 15,
        "examples/ has {count} examples, the gallery promises 15"
    );
}

#[test]
fn every_example_checks_clean() {
    let mut failures = Vec::new();
    for example in examples() {
        let run = qcsg()
            .args(["check", "--format", "json"])
            .arg(&example.path)
            .run();
        let diagnostics: Vec<serde_json::Value> = serde_json::from_slice(&run.stdout)
            .unwrap_or_else(|e| panic!("{}: check output is not JSON: {e}", example.file_name));
        let codes: BTreeSet<String> = diagnostics
            .iter()
            .filter(|d| d["severity"] != "info")
            .map(|d| d["code"].as_str().unwrap_or("?").to_owned())
            .collect();
        if run.status != 0 || codes != example.expected_warnings {
            failures.push(format!(
                "{}: expected {:?} from `qcsg check`, got exit {} and:\n{}",
                example.file_name,
                example.expected_warnings,
                run.status,
                serde_json::to_string_pretty(&diagnostics).unwrap()
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn every_example_is_formatted() {
    // Examples are what new users copy: they follow the house style of `qcsg fmt`.
    let mut unformatted = Vec::new();
    for example in examples() {
        let run = qcsg().args(["fmt", "--check"]).arg(&example.path).run();
        if run.status != 0 {
            unformatted.push(example.file_name);
        }
    }
    assert!(
        unformatted.is_empty(),
        "not formatted (run `qcsg fmt` on them): {unformatted:?}"
    );
}

#[test]
fn previews_are_current() {
    let scratch = scratch_dir("render");
    let bless = blessing();
    if bless {
        std::fs::create_dir_all(previews_dir()).expect("examples/previews/ can be made");
    }
    let mut failures = Vec::new();
    for example in examples() {
        let rendered = scratch.join(format!("{}.png", example.name));
        if let Err(stderr) = render(&example, &rendered) {
            failures.push(format!(
                "{}: `qcsg render` failed:\n{stderr}",
                example.file_name
            ));
            continue;
        }
        let preview = example.preview_path();
        if bless {
            std::fs::copy(&rendered, &preview).expect("the preview can be written");
            continue;
        }
        if !preview.exists() {
            failures.push(format!(
                "{}: no preview examples/previews/{}.png; QCSG_BLESS=1 cargo test -p qcsg-cli \
                 --test gallery writes it",
                example.file_name, example.name
            ));
            continue;
        }
        let stale = match compare(&rendered, &preview) {
            Ok(difference) if difference.within_tolerance() => continue,
            Ok(difference) => format!(
                "mean difference {:.2}, {} pixels ({:.2}%) differ visibly",
                difference.mean,
                difference.visible_pixels,
                100.0 * difference.share
            ),
            Err(message) => message,
        };
        failures.push(format!(
            "{}: the preview examples/previews/{}.png is stale ({stale}); if the change is \
             intended, rerun with QCSG_BLESS=1 cargo test -p qcsg-cli --test gallery",
            example.file_name, example.name
        ));
    }
    let _ = std::fs::remove_dir_all(&scratch);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn every_preview_belongs_to_an_example() {
    let names: BTreeSet<String> = examples().into_iter().map(|e| e.name).collect();
    let orphans: Vec<String> = std::fs::read_dir(previews_dir())
        .expect("examples/previews/ exists")
        .map(|entry| entry.expect("a directory entry").path())
        .filter(|path| {
            let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned());
            path.extension().is_none_or(|e| e != "png")
                || stem.is_none_or(|stem| !names.contains(&stem))
        })
        .map(|path| {
            let name = path.file_name().unwrap_or_default().to_string_lossy();
            format!("examples/previews/{name}")
        })
        .collect();
    assert!(
        orphans.is_empty(),
        "files in examples/previews/ with no example of that name (delete them): {orphans:?}"
    );
}

#[test]
fn the_gallery_page_shows_every_example() {
    let page = std::fs::read_to_string(examples_dir().join("README.md"))
        .expect("examples/README.md exists");
    let mut failures = Vec::new();
    for example in examples() {
        for needed in [
            format!("({})", example.file_name),
            format!("(previews/{}.png)", example.name),
            example.render_command(),
        ] {
            if !page.contains(&needed) {
                failures.push(format!("{}: the page lacks `{needed}`", example.file_name));
            }
        }
    }
    // And it names no example that does not exist.
    let files: BTreeSet<String> = examples().into_iter().map(|e| e.file_name).collect();
    let mut named = BTreeSet::new();
    for word in page.split(|c: char| c.is_whitespace() || "()[]`".contains(c)) {
        let word = word.strip_prefix("examples/").unwrap_or(word);
        let named_file = [".qcsg", ".scad"]
            .iter()
            .any(|extension| word.strip_suffix(extension).is_some_and(|s| !s.is_empty()));
        if named_file && !word.contains('/') && !files.contains(word) && named.insert(word) {
            failures.push(format!("the page names `{word}`, which is not an example"));
        }
    }
    assert!(
        failures.is_empty(),
        "examples/README.md:\n{}",
        failures.join("\n")
    );
}

#[test]
fn the_tolerance_catches_a_small_change() {
    // Bolt holes a little wider (1.8 to 2.1) must not pass as the committed wheel preview, and
    // the unchanged wheel must.
    let wheel = examples()
        .into_iter()
        .find(|e| e.name == "wheel")
        .expect("examples/wheel.qcsg exists");
    let scratch = scratch_dir("tolerance");
    let unchanged = scratch.join("unchanged.png");
    render(&wheel, &unchanged).expect("the wheel renders");
    let wider = Example {
        preview_args: [
            &["-D".to_owned(), "bolt_radius=2.1".to_owned()],
            &wheel.preview_args[..],
        ]
        .concat(),
        ..wheel
    };
    let changed = scratch.join("changed.png");
    render(&wider, &changed).expect("the changed wheel renders");
    let same = compare(&unchanged, &wider.preview_path()).expect("the preview is readable");
    let different = compare(&changed, &wider.preview_path()).expect("the preview is readable");
    let _ = std::fs::remove_dir_all(&scratch);
    assert!(same.within_tolerance(), "{same:?}");
    assert!(!different.within_tolerance(), "{different:?}");
}

#[test]
fn the_far_part_renders_as_at_the_origin() {
    // The precision example, moved from a million units out back to the origin, must match its
    // preview: the camera is fitted to the part, so only rounding could tell the two apart.
    let far = examples()
        .into_iter()
        .find(|e| e.name == "precision_part")
        .expect("examples/precision_part.qcsg exists");
    let at_origin = Example {
        preview_args: [
            &["-D".to_owned(), "site=[0, 0, 0]".to_owned()],
            &far.preview_args[..],
        ]
        .concat(),
        ..far
    };
    let scratch = scratch_dir("origin");
    let rendered = scratch.join("origin.png");
    render(&at_origin, &rendered).expect("the part renders at the origin");
    let difference =
        compare(&rendered, &at_origin.preview_path()).expect("the preview is readable");
    let _ = std::fs::remove_dir_all(&scratch);
    assert!(difference.within_tolerance(), "{difference:?}");
}
