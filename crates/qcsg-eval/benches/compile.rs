//! The compiler front to back on generated and written programs:
//!
//! - `thousand_instances`: `benches/thousand_instances.scad` (1,000 primitive instances) through
//!   parse + check, evaluation, and DNF construction with pruning, each stage and all together;
//! - `variables_N`: a top level of N variables that all read the first one, evaluated (the cost
//!   of looking names up in a large scope).
//!
//! Before timing, the DNF counts of the 1,000-instance scene are printed.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use qcsg_csg::{DnfOptions, build_dnf};
use qcsg_eval::{EvalOptions, evaluate};
use qcsg_sema::{Analysis, CheckOptions, FsLoader, check_file};

const THOUSAND: &str = include_str!("thousand_instances.scad");

fn check(text: &str) -> Analysis {
    let analysis = check_file(
        "thousand_instances.scad",
        text.to_owned(),
        &CheckOptions::default(),
        &FsLoader,
    );
    assert!(
        !analysis.diagnostics.iter().any(|d| d.is_error()),
        "{:?}",
        analysis.diagnostics
    );
    analysis
}

/// A top level of `n` variables, each reading the first.
fn many_variables(n: usize) -> String {
    let mut text = String::from("v0 = 1;\n");
    for i in 1..n {
        text.push_str(&format!("v{i} = v0 + {i};\n"));
    }
    text.push_str(&format!("cube(v{} / {n});\n", n - 1));
    text
}

fn bench(c: &mut Criterion) {
    let analysis = check(THOUSAND);
    let evaluation = evaluate(&analysis, &EvalOptions::default());
    assert!(!evaluation.has_errors());
    let dnf = build_dnf(&evaluation.dag, &DnfOptions::default()).expect("bounded scene");
    eprintln!("thousand_instances: {}", dnf.stats);

    let mut group = c.benchmark_group("thousand_instances");
    group.bench_function("parse_and_check", |b| b.iter(|| check(black_box(THOUSAND))));
    group.bench_function("evaluate", |b| {
        b.iter(|| evaluate(black_box(&analysis), &EvalOptions::default()))
    });
    group.bench_function("dnf", |b| {
        b.iter(|| build_dnf(black_box(&evaluation.dag), &DnfOptions::default()))
    });
    group.bench_function("evaluate_and_dnf", |b| {
        b.iter(|| {
            let evaluation = evaluate(black_box(&analysis), &EvalOptions::default());
            build_dnf(&evaluation.dag, &DnfOptions::default())
        })
    });
    group.bench_function("all", |b| {
        b.iter(|| {
            let analysis = check(black_box(THOUSAND));
            let evaluation = evaluate(&analysis, &EvalOptions::default());
            build_dnf(&evaluation.dag, &DnfOptions::default())
        })
    });
    group.finish();

    let mut group = c.benchmark_group("variables");
    for n in [1_000, 10_000] {
        let analysis = check(&many_variables(n));
        group.bench_function(format!("evaluate_{n}"), |b| {
            b.iter(|| evaluate(black_box(&analysis), &EvalOptions::default()))
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench
}
criterion_main!(benches);
