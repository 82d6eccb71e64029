//! The stability cases of `tests/stability/` as a table: each case's outcome against its
//! header's expectation and its measured errors.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use qcsg_bench::stability::{self, run_case};

use crate::{ms, sci, secs};

/// Writes the stability table; returns (cases, as expected, keeping every guarantee).
pub fn stability_section(md: &mut String, root: &Path) -> Result<(usize, usize, usize), String> {
    let mut counts = (0, 0, 0);
    let dir = root.join("tests/stability");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map_err(|e| format!("cannot list {}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "qcsg" || e == "scad"))
        .collect();
    files.sort();
    let _ = writeln!(md, "## 8. Stability cases\n");
    let _ = writeln!(
        md,
        "The {} scenes of `tests/stability/`, as `cargo test -p qcsg-bench --test stability` runs \
         them (the test checks each outcome against the `// expect:` line of its file). Coverage \
         is over surface and feature-curve reference points, in units of the radius (≤ 1 is \
         the guarantee); on-surface error relative to the diagonal (limit {:.0e}, plus 8 ulps of the \
         largest coordinate for scenes far from the origin).\n",
        files.len(),
        qcsg_bench::measure::ON_SURFACE_LIMIT
    );
    let _ = writeln!(
        md,
        "| case | expect | as expected | failed checks | samples | r / diag | coverage / r | on-surface / diag | reference points | sampling ms | stresses |"
    );
    let _ = writeln!(md, "|---|---|---|---|---:|---:|---:|---:|---:|---:|---|");
    for path in &files {
        let name = path
            .file_stem()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        let start = Instant::now();
        let result = run_case(path)?;
        eprintln!("stability {name}: {:.2} s", secs(start.elapsed()));
        let expect = match &result.header.expect {
            stability::Expect::Ok => "ok".to_owned(),
            stability::Expect::Empty => "empty".to_owned(),
            stability::Expect::Error(c) => format!("error {c}"),
            stability::Expect::KnownFailure(c) => format!("known-failure {}", stability::names(c)),
        };
        counts.0 += 1;
        if result.failed.is_empty() {
            counts.2 += 1;
        }
        let verdict = match result.verdict() {
            Ok(()) => {
                counts.1 += 1;
                "yes".to_owned()
            }
            Err(why) => format!("**no**: {}", why.replace('|', "/")),
        };
        let (samples, cov, on, time) = match &result.measured {
            Some(m) => (
                m.sampling.samples.len().to_string(),
                format!("{:.3}", m.coverage_over_radius()),
                sci(m.on_surface),
                ms(m.time),
            ),
            None => ("–".into(), "–".into(), "–".into(), "–".into()),
        };
        let _ = writeln!(
            md,
            "| {name} | {expect} | {verdict} | {} | {samples} | {} | {cov} | {on} | {} + {} | {time} | {} |",
            if result.failed.is_empty() {
                "–".into()
            } else {
                stability::names(&result.failed)
            },
            result.header.relative_radius,
            result.reference_counts.0,
            result.reference_counts.1,
            result.header.stresses.replace('|', "/")
        );
    }
    let _ = writeln!(md);
    Ok(counts)
}
