//! OpenSCAD's deprecated `child()` and `assign()` at run time, where OpenSCAD 2021.01 ignores an
//! argument or warns: the echo output is OpenSCAD's, the diagnostics are at the argument or call.
//! (`tests/eval/deprecated.scad` compares the ordinary cases with OpenSCAD's output.)

mod common;

use common::{codes, eval};
use qcsg_eval::codes as c;

fn echoes(text: &str) -> (Vec<String>, Vec<&'static str>) {
    let e = eval(text);
    let lines = e.echo_lines().iter().map(|l| l.to_string()).collect();
    (lines, codes(&e))
}

#[test]
fn child_of_a_non_number_is_the_first_child_with_a_warning() {
    // OpenSCAD 2021.01: `child([1, 0])` and `child("a")` both take child 0.
    let (lines, codes) =
        echoes("module m() { child([1, 0]); child(\"a\"); }\nm() { echo(0); echo(1); }\n");
    assert_eq!(lines, ["ECHO: 0", "ECHO: 0"]);
    assert_eq!(
        codes.iter().filter(|&&x| x == c::IGNORED_ARGUMENT).count(),
        2,
        "{codes:?}"
    );
}

#[test]
fn child_index_out_of_bounds_is_an_error() {
    // OpenSCAD warns and instantiates nothing; qcsg reports it at the call and carries on.
    for index in ["2", "-1", "0 / 0", "1e300"] {
        let text =
            format!("module m() child({index});\nm() {{ echo(0); echo(1); }}\necho(\"after\");\n");
        let (lines, codes) = echoes(&text);
        assert!(codes.contains(&c::MODULE_ARGUMENT), "{index}: {codes:?}");
        assert_eq!(lines, ["ECHO: \"after\""], "{index}");
    }
    // A negative fraction truncates to 0, as OpenSCAD's `trunc` does.
    let (lines, _) = echoes("module m() child(-0.5);\nm() echo(0);\n");
    assert_eq!(lines, ["ECHO: 0"]);
}

#[test]
fn child_outside_a_module_and_without_children_is_nothing() {
    let (lines, codes) = echoes("child(0);\nmodule m() child();\nm();\necho(1);\n");
    // Outside a module there are no children; inside one without children, index 0 is out of
    // bounds.
    assert_eq!(lines, ["ECHO: 1"]);
    assert_eq!(
        codes.iter().filter(|&&x| x == c::MODULE_ARGUMENT).count(),
        1,
        "{codes:?}"
    );
}

#[test]
fn assign_ignores_positional_arguments_unevaluated() {
    let (lines, codes) = echoes("assign(echo(\"positional\") 1, a = 2) echo(a = a);\n");
    assert_eq!(lines, ["ECHO: a = 2"]);
    assert!(codes.contains(&c::IGNORED_ARGUMENT), "{codes:?}");
}

/// OpenSCAD 2021.01 looks special variables up dynamically, in the scope `assign` is filling:
/// a `$`-binding is seen by the values after it, an ordinary binding by none.
#[test]
fn assign_sets_special_variables_for_its_child_and_later_values() {
    let (lines, _) = echoes(
        "$r = 1;\nmodule show() echo($r);\nassign($r = 5, s = $r) { show(); echo(s); }\nshow();\n",
    );
    assert_eq!(lines, ["ECHO: 5", "ECHO: 5", "ECHO: 1"]);
    let (lines, _) = echoes("$r = 1;\nassign(s = $r, $r = 5, t = $r) echo(s, t);\n");
    assert_eq!(lines, ["ECHO: 1, 5"]);
    let (lines, _) = echoes("r = 1;\nassign(s = r, r = 5, t = r) echo(s, t);\n");
    assert_eq!(lines, ["ECHO: 1, 1"]);
}
