//! The stability suite: every scene in `tests/stability/` (repository root) runs through check →
//! evaluate → DNF → sample → CPU render without a panic and without NaN, and either keeps every
//! guarantee or stops with the diagnostic its header names (`// expect: …`, see
//! `qcsg_bench::stability`). A known failure must fail exactly as recorded.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;

use qcsg_bench::stability::{CaseResult, run_case};

/// Every case file, or only those whose name contains `QCSG_STABILITY_CASE` when it is set.
fn case_files() -> Vec<PathBuf> {
    let only = std::env::var("QCSG_STABILITY_CASE").ok();
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/stability");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|err| panic!("cannot list {}: {err}", dir.display()))
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "qcsg" || e == "scad"))
        .filter(|p| {
            only.as_deref().is_none_or(|o| {
                p.file_name()
                    .is_some_and(|n| n.to_string_lossy().contains(o))
            })
        })
        .collect();
    files.sort();
    files
}

fn describe(name: &str, r: &CaseResult) -> String {
    let mut line = format!(
        "{name}: failed [{}]",
        qcsg_bench::stability::names(&r.failed)
    );
    if let Some(m) = &r.measured {
        line.push_str(&format!(
            ", {} samples in {:.2} s, on-surface {:.2e}, coverage {:.3} r (edges {:.3} r), beyond reach {}+{}, off-surface {}, unresolved {}",
            m.sampling.samples.len(),
            m.time.as_secs_f64(),
            m.on_surface,
            m.coverage.max_distance / m.radius,
            m.edge_coverage.max_distance / m.radius,
            m.coverage.beyond_reach,
            m.edge_coverage.beyond_reach,
            m.off_csg_surface,
            m.sampling.stats.unresolved(),
        ));
    }
    line.push_str(&format!(
        ", refs {}+{}, pixels {}, errors {:?}",
        r.reference_counts.0, r.reference_counts.1, r.image_hits, r.error_codes
    ));
    line
}

#[test]
fn stability_suite() {
    let files = case_files();
    assert!(
        files.len() >= 25 || std::env::var_os("QCSG_STABILITY_CASE").is_some(),
        "the suite needs at least 25 cases, found {}",
        files.len()
    );
    let mut problems = Vec::new();
    for path in &files {
        let name = path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        let start = std::time::Instant::now();
        let outcome = catch_unwind(AssertUnwindSafe(|| run_case(path)));
        eprintln!("{name}: {:.2} s", start.elapsed().as_secs_f64());
        match outcome {
            Err(_) => problems.push(format!("{name}: panicked")),
            Ok(Err(err)) => problems.push(format!("{name}: {err}")),
            Ok(Ok(result)) => {
                eprintln!("{}", describe(&name, &result));
                if let Err(why) = result.verdict() {
                    problems.push(format!("{name}: {why}"));
                }
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
