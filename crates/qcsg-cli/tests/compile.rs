//! End-to-end tests of `qcsg compile`: the DAG and DNF formats of docs/cli.md, the text forms, `-D`,
//! the limit flags and the diagnostics at the span that crossed a limit, and exit codes. Programs
//! come on standard input (named `<stdin>` in diagnostics).

use qcsg_testkit::cli::{Invocation, Run};
use serde_json::Value;

/// Runs `qcsg compile - args…` with `program` on standard input.
fn compile(program: &str, args: &[&str]) -> Run {
    Invocation::new(env!("CARGO_BIN_EXE_qcsg"))
        .args(["compile", "-"])
        .args(args)
        .stdin(program)
        .run()
}

fn json(run: &Run) -> Value {
    assert_eq!(run.status, 0, "{}", run.stderr);
    serde_json::from_str(run.stdout_text()).unwrap_or_else(|e| panic!("{e}: {}", run.stdout_text()))
}

/// `error[CODE]` followed (in the excerpt header) by `<stdin>:LINE:COL`.
fn reports_at(run: &Run, code: &str, line_col: &str) -> bool {
    run.stderr
        .split(&format!("error[{code}]"))
        .skip(1)
        .any(|after| {
            after
                .lines()
                .take(4)
                .any(|l| l.contains(&format!("<stdin>:{line_col}")))
        })
}

#[test]
fn dnf_json_has_the_contract_fields() {
    let run = compile(
        "difference() {\n  cube(2, center = true);\n  translate([1e6, 0, 0]) sphere(1);\n  sphere(1.2);\n}\n",
        &["--emit", "dnf", "--format", "json"],
    );
    let dnf = json(&run);
    let quadrics = dnf["quadrics"].as_array().expect("quadrics");
    // cube: 3 slabs, sphere(1.2): 1; the far sphere misses the cube's box and is pruned.
    assert_eq!(quadrics.len(), 4, "{}", run.stdout_text());
    for (i, q) in quadrics.iter().enumerate() {
        assert_eq!(q["id"], i);
        assert_eq!(q["origin"].as_array().unwrap().len(), 3);
        assert_eq!(q["coefficients"].as_array().unwrap().len(), 10);
        assert!(q["kind"].is_string());
        assert!(q["source"]["file"].is_string());
        assert_eq!(q["source"]["byte_range"].as_array().unwrap().len(), 2);
    }
    assert_eq!(dnf["terms"], serde_json::json!([[0, 1, 2, 3]]));
    for (corner, value) in [("min", -1.0), ("max", 1.0)] {
        for x in dnf["bounds"][corner].as_array().unwrap() {
            assert!(
                (x.as_f64().unwrap() - value).abs() < 1e-9,
                "{}",
                dnf["bounds"]
            );
        }
    }
    let passes = dnf["stats"]["passes"].as_array().expect("stats.passes");
    assert!(passes.iter().any(|p| p["pass"] == "subsumed_terms"));
}

#[test]
fn dag_json_shares_repeated_instances() {
    let run = compile(
        "module peg() cylinder(h = 2, r = 0.5);\nfor (i = [0 : 9]) translate([i, 0, 0]) peg();\n",
        &["--emit", "dag", "--format", "json"],
    );
    let dag = json(&run);
    let text = dag.to_string();
    // Ten instances, one cylinder: a cylinder is two leaves under one intersection.
    let leaves = dag["nodes"]
        .as_array()
        .expect("nodes")
        .iter()
        .filter(|n| n.get("quadric").is_some())
        .count();
    assert_eq!(leaves, 2, "{text}");
}

#[test]
fn dnf_text_is_one_term_per_line_with_kinds_and_sources() {
    let run = compile(
        "sphere(1);\ntranslate([5, 0, 0]) cube(1);\n",
        &["--emit", "dnf"],
    );
    assert_eq!(run.status, 0, "{}", run.stderr);
    assert!(
        run.stdout_text().contains(" sphere "),
        "{}",
        run.stdout_text()
    );
    assert!(
        run.stdout_text().contains(" slab "),
        "{}",
        run.stdout_text()
    );
    assert!(
        run.stdout_text().contains("<stdin>:1:1"),
        "{}",
        run.stdout_text()
    );
    assert!(
        run.stdout_text().contains("<stdin>:2:"),
        "{}",
        run.stdout_text()
    );
}

#[test]
fn defines_override_variables() {
    let program = "n = 1;\nfor (i = [1 : n]) translate([3 * i, 0, 0]) sphere(1);\n";
    let terms = |args: &[&str]| {
        let mut all = vec!["--emit", "dnf", "--format", "json"];
        all.extend_from_slice(args);
        json(&compile(program, &all))["terms"]
            .as_array()
            .unwrap()
            .len()
    };
    assert_eq!(terms(&[]), 1);
    assert_eq!(terms(&["-D", "n=4"]), 4);
    let run = compile(program, &["--emit", "dnf", "-D", "n=1 +"]);
    assert_eq!(run.status, 1);
    assert!(run.stderr.contains("E0561"), "{}", run.stderr);
}

#[test]
fn the_term_limit_is_an_error_at_the_part_that_crossed_it_and_a_flag_raises_it() {
    // A block minus 8 cubes that all overlap: the normal form multiplies out.
    let program = "difference() {\n  cube(10);\n  for (i = [0 : 7]) translate([i / 2, i / 3, 1]) cube(3);\n}\n";
    let run = compile(program, &["--emit", "dnf", "--max-terms", "20"]);
    assert_eq!(run.status, 1, "{}", run.stdout_text());
    assert!(run.stdout.is_empty());
    // At the subtracted cube whose expansion crossed the limit.
    assert!(reports_at(&run, "E0601", "3:50"), "{}", run.stderr);
    let run = compile(program, &["--emit", "dnf", "--max-terms", "1000000"]);
    assert_eq!(run.status, 0, "{}", run.stderr);
}

#[test]
fn evaluation_limits_have_flags_and_spans() {
    let program = "function f(n) = n == 0 ? 0 : 1 + f(n - 1);\necho(f(300));\ncube(1);\n";
    let run = compile(program, &["--emit", "dnf", "--max-recursion", "100"]);
    assert_eq!(run.status, 1);
    assert!(reports_at(&run, "E0556", "1:34"), "{}", run.stderr);
    assert_eq!(compile(program, &["--emit", "dnf"]).status, 0);

    let program = "for (i = [0 : 99]) translate([2 * i, 0, 0]) cube(1);\n";
    let run = compile(program, &["--emit", "dag", "--max-instances", "10"]);
    assert_eq!(run.status, 1);
    assert!(reports_at(&run, "E0559", "1:"), "{}", run.stderr);
    let run = compile(program, &["--emit", "dag", "--max-iterations", "10"]);
    assert!(reports_at(&run, "E0557", "1:"), "{}", run.stderr);
    let run = compile(
        "x = [0 : 1e6];\necho(len([for (i = x) i]));\ncube(1);\n",
        &["--emit", "dag", "--max-vector-len", "1000"],
    );
    assert!(run.stderr.contains("error[E0558]"), "{}", run.stderr);
}

#[test]
fn an_unbounded_result_names_the_unbounded_part() {
    let run = compile(
        "cube(1);\ntranslate([4, 0, 0]) halfspace([1, 0, 0]);\n",
        &["--emit", "dnf"],
    );
    assert_eq!(run.status, 1);
    assert!(reports_at(&run, "E0600", "2:22"), "{}", run.stderr);
    // Clipped by a finite solid it is fine.
    let run = compile(
        "intersection() { cube(1); halfspace([1, 0, 0], 0.5); }\n",
        &["--emit", "dnf"],
    );
    assert_eq!(run.status, 0, "{}", run.stderr);
}

#[test]
fn every_runtime_error_of_a_run_is_reported() {
    let run = compile(
        "x = [1];\na = x[3] + 1;\nb = x[4] * 2;\ncube(1);\n",
        &["--emit", "dnf"],
    );
    assert_eq!(run.status, 1);
    assert!(run.stdout.is_empty());
    assert!(reports_at(&run, "E0550", "2:5"), "{}", run.stderr);
    assert!(reports_at(&run, "E0550", "3:5"), "{}", run.stderr);
}
