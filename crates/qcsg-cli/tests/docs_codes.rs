//! `docs/language.md` stays true: its table of diagnostic codes lists exactly the codes the checker
//! can report (those of `qcsg_syntax::codes::ALL`, `qcsg_sema::codes::ALL`, the evaluator's
//! `qcsg_eval::codes::ALL` and the scene IR's `qcsg_csg::codes::ALL`), and its examples parse.

use std::collections::BTreeSet;
use std::path::Path;

/// The heading of the table's section in the manual.
const SECTION: &str = "## Diagnostic codes";

/// The codes in the first column of the table under [`SECTION`], in order of appearance.
fn documented_codes(manual: &str) -> Vec<String> {
    let start = manual
        .find(SECTION)
        .unwrap_or_else(|| panic!("docs/language.md has no `{SECTION}`"));
    let section = &manual[start + SECTION.len()..];
    let section = section.find("\n## ").map_or(section, |end| &section[..end]);
    section
        .lines()
        .filter_map(|line| line.trim().strip_prefix("| `"))
        .filter_map(|rest| rest.split_once('`'))
        .map(|(code, _)| code.to_owned())
        .collect()
}

fn manual() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/language.md");
    std::fs::read_to_string(&path).expect("docs/language.md is readable")
}

#[test]
fn manual_documents_every_code_exactly_once() {
    let manual = manual();
    let documented = documented_codes(&manual);
    let unique: BTreeSet<&str> = documented.iter().map(String::as_str).collect();
    assert_eq!(
        unique.len(),
        documented.len(),
        "a code is listed twice: {documented:?}"
    );

    let known: BTreeSet<&str> = qcsg_syntax::codes::ALL
        .iter()
        .chain(qcsg_sema::codes::ALL)
        .chain(qcsg_eval::codes::ALL)
        .chain(qcsg_csg::codes::ALL)
        .map(|(code, _)| *code)
        .collect();
    let undocumented: Vec<_> = known.difference(&unique).collect();
    let unknown: Vec<_> = unique.difference(&known).collect();
    assert!(
        undocumented.is_empty() && unknown.is_empty(),
        "docs/language.md's table of codes is out of date:\n  missing from the table: \
         {undocumented:?}\n  in the table but reported by no crate: {unknown:?}"
    );
}

#[test]
fn table_parser_reads_the_first_column_of_the_section_only() {
    let manual = "| `E9999` | before |\n## Diagnostic codes\n\n| code | meaning |\n| --- | --- |\n\
                  | `E0001` | a |\n| `W0101` | `b` |\n\n## Next\n| `E0002` | after |\n";
    assert_eq!(documented_codes(manual), ["E0001", "W0101"]);
}

/// A code's letter says its severity: `E` errors, `W` warnings.
#[test]
fn scene_codes_are_named_by_their_severity() {
    assert!(qcsg_csg::codes::SINGULAR_TRANSFORM.starts_with('W'));
    for code in [
        qcsg_csg::codes::UNBOUNDED,
        qcsg_csg::codes::TERM_LIMIT,
        qcsg_csg::codes::NO_ROOT,
    ] {
        assert!(code.starts_with('E'), "{code}");
    }
}

/// Examples are fragments (they may name things defined elsewhere), but each must be valid syntax.
#[test]
fn manual_examples_have_no_syntax_errors() {
    let manual = manual();
    let examples: Vec<&str> = manual
        .split("```openscad\n")
        .skip(1)
        .map(|rest| rest.split_once("```").expect("closed code block").0)
        .collect();
    assert!(examples.len() >= 10, "found {} examples", examples.len());
    for example in examples {
        let parse = qcsg_syntax::parse(example, qcsg_diag::FileId(0));
        let messages: Vec<String> = parse
            .diagnostics
            .iter()
            .map(|d| format!("{}: {}", d.code, d.message))
            .collect();
        assert!(messages.is_empty(), "{messages:?} in\n{example}");
    }
}
