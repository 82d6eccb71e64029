//! The pruning report of `docs/compiler.md`: every example of `examples/` is evaluated and put
//! in normal form, and the tables of what construction and each pruning pass removed must equal
//! the ones on the page. The test fails when the page is stale; after an intended change to an
//! example or to the compiler, write the tables again with
//!
//! ```sh
//! QCSG_BLESS=1 cargo test -p qcsg-eval --test compiler_doc
//! ```

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use qcsg_csg::{DnfOptions, DnfSize, DnfStats, build_dnf, unpruned_size};
use qcsg_eval::{EvalOptions, evaluate};
use qcsg_sema::{CheckOptions, FsLoader, check_file};

const START: &str = "<!-- pruning-report:start (written by QCSG_BLESS=1 cargo test -p qcsg-eval --test compiler_doc) -->";
const END: &str = "<!-- pruning-report:end -->";

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A count that may be astronomically large.
fn count(x: f64) -> String {
    if x < 1e9 {
        format!("{x:.0}")
    } else {
        format!("{x:.2e}")
    }
}

/// The DNF statistics of every example, by file name, with the unpruned size.
fn example_stats() -> Vec<(String, DnfStats, DnfSize)> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(root().join("examples"))
        .expect("examples/ exists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "qcsg" || x == "scad"))
        .collect();
    paths.sort();
    assert!(!paths.is_empty(), "no examples found");
    // The benchmark's scene too, for its counts.
    paths.push(root().join("crates/qcsg-eval/benches/thousand_instances.scad"));
    paths
        .iter()
        .map(|path| {
            let name = match path.parent().and_then(|p| p.file_name()) {
                Some(dir) if dir == "benches" => "(benchmark) thousand_instances.scad".to_string(),
                _ => path.file_name().unwrap().to_string_lossy().into_owned(),
            };
            let text = std::fs::read_to_string(path).expect("readable example");
            let analysis = check_file(
                &path.to_string_lossy(),
                text,
                &CheckOptions::default(),
                &FsLoader,
            );
            assert!(
                !analysis.diagnostics.iter().any(|d| d.is_error()),
                "{name}: {:?}",
                analysis.diagnostics
            );
            let evaluation = evaluate(&analysis, &EvalOptions::default());
            assert!(
                !evaluation.has_errors(),
                "{name}: {:?}",
                evaluation.diagnostics
            );
            let dnf = build_dnf(&evaluation.dag, &DnfOptions::default())
                .unwrap_or_else(|e| panic!("{name}: {e:?}"));
            let root = evaluation.dag.root().expect("a root");
            let size = unpruned_size(&evaluation.dag, root);
            (name, dnf.stats, size)
        })
        .collect()
}

/// The two tables: construction counters, then terms / literals around each pass.
fn report(stats: &[(String, DnfStats, DnfSize)]) -> String {
    let mut out = String::new();
    out.push_str(
        "During construction (counts of the DNF builder; a term dropped early never multiplies):\n\n\
         | example | DAG nodes | leaf visits | literals (merged) | terms dropped: outside operand box / empty box / outside a literal / duplicate / subsumed | subtracted operands skipped | literals not added: inside / duplicate | peak terms |\n\
         | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n",
    );
    for (name, s, _) in stats {
        let c = &s.construction;
        writeln!(
            out,
            "| {name} | {} | {} | {} ({}) | {} / {} / {} / {} / {} | {} | {} / {} | {} |",
            s.dag_nodes,
            c.leaves_visited,
            c.literals_interned,
            c.literals_merged,
            c.terms_outside_operand_bounds,
            c.terms_empty_bounds,
            c.terms_outside_literal,
            c.terms_duplicate,
            c.terms_subsumed,
            c.operands_skipped,
            c.literals_inside,
            c.literals_duplicate,
            c.peak_terms,
        )
        .unwrap();
    }
    let passes: Vec<&str> = stats
        .first()
        .map(|(_, s, _)| s.passes.iter().map(|p| p.pass).collect())
        .unwrap_or_default();
    out.push_str(
        "\nTerms / literal occurrences: multiplied out with no pruning at all, after construction \
         (before the first pass), and after each pass over the finished DNF; the size of the \
         quadric table before and after the passes:\n\n",
    );
    out.push_str("| example | unpruned | constructed |");
    for pass in &passes {
        write!(out, " {pass} |").unwrap();
    }
    out.push_str(" quadrics |\n| --- | ---: | ---: |");
    for _ in &passes {
        out.push_str(" ---: |");
    }
    out.push_str(" ---: |\n");
    for (name, s, size) in stats {
        let names: Vec<&str> = s.passes.iter().map(|p| p.pass).collect();
        assert_eq!(names, passes, "{name}: the passes differ between examples");
        let first = s.passes.first().expect("at least one pass");
        write!(
            out,
            "| {name} | {} / {} | {} / {} |",
            count(size.terms),
            count(size.literals),
            first.terms_before,
            first.literals_before
        )
        .unwrap();
        for p in &s.passes {
            let changed = p.terms_after != p.terms_before || p.literals_after != p.literals_before;
            let (open, close) = if changed { ("**", "**") } else { ("", "") };
            write!(
                out,
                " {open}{} / {}{close} |",
                p.terms_after, p.literals_after
            )
            .unwrap();
        }
        let last = s.passes.last().expect("at least one pass");
        writeln!(
            out,
            " {} → {} |",
            first.quadrics_before, last.quadrics_after
        )
        .unwrap();
    }
    let changed = stats
        .iter()
        .filter(|(_, s, _)| {
            s.passes
                .iter()
                .any(|p| p.terms_after != p.terms_before || p.literals_after != p.literals_before)
        })
        .count();
    writeln!(
        out,
        "\nBold: the pass changed the counts. The passes changed terms or literals in {changed} of \
         these {} scenes.",
        stats.len()
    )
    .unwrap();
    out
}

#[test]
fn the_pruning_report_is_current() {
    let page_path = root().join("docs/compiler.md");
    let page = std::fs::read_to_string(&page_path).expect("docs/compiler.md exists");
    let (Some(start), Some(end)) = (page.find(START), page.find(END)) else {
        panic!("docs/compiler.md lacks the lines\n{START}\n{END}");
    };
    assert!(start < end, "the report's markers are out of order");
    let body_start = start + START.len() + 1;
    let current = &page[body_start.min(end)..end];
    let expected = report(&example_stats());
    if current == expected {
        return;
    }
    if std::env::var_os("QCSG_BLESS").is_some_and(|v| v == "1") {
        let mut updated = page[..body_start.min(end)].to_string();
        if body_start > end {
            updated.push('\n');
        }
        updated.push_str(&expected);
        updated.push_str(&page[end..]);
        std::fs::write(&page_path, updated).expect("docs/compiler.md writable");
        return;
    }
    panic!(
        "the pruning report of docs/compiler.md is stale; write it again with\n  \
         QCSG_BLESS=1 cargo test -p qcsg-eval --test compiler_doc\n--- on the page\n{current}\n--- now\n{expected}"
    );
}
