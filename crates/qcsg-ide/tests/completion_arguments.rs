//! Argument-name completion inside argument lists: built-in and user modules and functions,
//! definitions of `use`d files, function literals, names already given, and unfinished text.
//!
//! Each program marks the cursor with `|`.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use qcsg_diag::LineIndex;
use qcsg_ide::*;

#[derive(Default)]
struct Files(HashMap<PathBuf, String>);

impl FileLoader for Files {
    fn load(&self, path: &Path) -> std::io::Result<String> {
        self.0
            .get(path)
            .cloned()
            .ok_or_else(|| std::io::ErrorKind::NotFound.into())
    }
}

const LIBRARY: &str = "/// A library part.\n/// `size`: the edge length\nmodule part(size = 2, hollow = false) cube(size);\n/// Twice its argument.\nfunction lib_twice(x) = 2 * x;\n";

/// The completions at the `|` of `marked` (which is removed), in a file beside `lib.scad`.
fn complete(marked: &str) -> Vec<CompletionItem> {
    let offset = marked.find('|').expect("a cursor mark");
    let text = marked.replacen('|', "", 1);
    let files = Files(
        [(PathBuf::from("dir/lib.scad"), LIBRARY.to_owned())]
            .into_iter()
            .collect(),
    );
    let analysis = Analysis::new(
        "dir/main.qcsg",
        text.clone(),
        &CheckOptions::default(),
        &files,
    );
    analysis.completions(LineIndex::new(&text).line_col(&text, offset))
}

/// The labels of the argument-name items, in order.
fn argument_names(items: &[CompletionItem]) -> Vec<&str> {
    items
        .iter()
        .filter(|item| item.kind == CompletionKind::Parameter)
        .map(|item| item.label.as_str())
        .collect()
}

/// The argument names other than `$` special variables.
fn parameters(items: &[CompletionItem]) -> Vec<&str> {
    argument_names(items)
        .into_iter()
        .filter(|label| !label.starts_with('$'))
        .collect()
}

fn item<'a>(items: &'a [CompletionItem], label: &str) -> &'a CompletionItem {
    items
        .iter()
        .find(|item| item.label == label)
        .unwrap_or_else(|| panic!("no `{label}` in {:?}", labels(items)))
}

fn labels(items: &[CompletionItem]) -> Vec<&str> {
    items.iter().map(|item| item.label.as_str()).collect()
}

/// Argument names come first, in the list and by their sort keys (in their own order), before
/// everything else.
fn assert_ranked(items: &[CompletionItem]) {
    let names = argument_names(items).len();
    assert!(
        names > 0
            && items[..names]
                .iter()
                .all(|item| item.kind == CompletionKind::Parameter),
        "{:?}",
        labels(items)
    );
    let keys: Vec<_> = items.iter().map(|item| item.sort_text.clone()).collect();
    assert!(keys.iter().all(Option::is_some), "{keys:?}");
    assert!(
        keys[..names].windows(2).all(|pair| pair[0] < pair[1]),
        "{keys:?}"
    );
    let last_name = &keys[names - 1];
    assert!(keys[names..].iter().all(|key| key > last_name), "{keys:?}");
}

#[test]
fn builtin_module_offers_its_parameters_first_with_defaults_and_docs() {
    let items = complete("sphere(|);\n");
    assert_ranked(&items);
    assert_eq!(parameters(&items), ["r =", "d ="]);
    let r = item(&items, "r =");
    assert_eq!(r.insert_text.as_deref(), Some("r = "));
    assert_eq!(r.detail.as_deref(), Some("a number · default 1"));
    let doc = r.doc.as_deref().unwrap_or_default();
    assert!(
        doc.contains("module sphere(r, d)") && doc.contains("a ball"),
        "{doc}"
    );
    // An argument may be any expression: those follow, but modules are no expression.
    let all = labels(&items);
    assert!(
        all.contains(&"PI") && all.contains(&"sin") && all.contains(&"true"),
        "{all:?}"
    );
    assert!(
        !all.contains(&"cube") && !all.contains(&"module"),
        "{all:?}"
    );

    // The name being typed narrows the list; `r =` still comes first.
    let typed = complete("sphere(r|);\n");
    assert_eq!(labels(&typed)[0], "r =");
    assert!(labels(&typed).contains(&"round"));

    let cylinder = complete("cylinder(|);\n");
    assert_eq!(
        item(&cylinder, "center =").detail.as_deref(),
        Some("a boolean (`true` or `false`) · default false")
    );
    assert_eq!(
        parameters(&cylinder),
        [
            "h =", "r1 =", "r2 =", "center =", "r =", "d =", "d1 =", "d2 ="
        ]
    );
    // A value the documentation shows only as an example is no default.
    assert_eq!(
        item(&complete("ellipsoid(|);\n"), "r =").detail.as_deref(),
        Some("a number or a vector of numbers")
    );
}

#[test]
fn special_variables_are_argument_names_of_every_module_call() {
    let items = complete("$explode = 0;\nmodule m() cube(1 + $explode);\nm(|);\n");
    let names = argument_names(&items);
    for special in ["$explode =", "$t =", "$fn =", "$fa =", "$fs ="] {
        assert!(names.contains(&special), "{special} in {names:?}");
    }
    // The module instance keeps these itself.
    assert!(!names.contains(&"$children ="), "{names:?}");
    let fn_item = item(&items, "$fn =");
    assert_eq!(fn_item.insert_text.as_deref(), Some("$fn = "));
    assert!(
        fn_item
            .doc
            .as_deref()
            .unwrap_or_default()
            .contains("no effect")
    );

    // After a typed `$`, the items replace it rather than follow it.
    let marked = "sphere($f|);\n";
    let items = complete(marked);
    assert_eq!(argument_names(&items)[..3], ["$fn =", "$fa =", "$fs ="]);
    let replace = item(&items, "$fn =").replace.expect("a range");
    assert_eq!((replace.start.character, replace.end.character), (7, 9));
}

#[test]
fn builtin_function_arguments_are_positional_only() {
    // The checker rejects `sin(x = 1)`: OpenSCAD binds a built-in function's arguments by
    // position whatever their names. Expressions are offered, no names.
    let items = complete("y = 1;\nx = sin(|);\n");
    assert_eq!(argument_names(&items), Vec::<&str>::new());
    let all = labels(&items);
    assert!(all.contains(&"y") && all.contains(&"cos"), "{all:?}");
    let unfinished = complete("x = max(1, |");
    assert_eq!(argument_names(&unfinished), Vec::<&str>::new());
    assert!(labels(&unfinished).contains(&"min"));
}

#[test]
fn user_module_offers_its_parameters_with_defaults_and_doc_lines() {
    let program = "/// A flat ring.\n/// `outer`: the outer radius\n/// `inner`: the hole's radius\nmodule washer(outer = 10, inner, thickness = 1) {\n    difference() {\n        cylinder(h = thickness, r = outer);\n        cylinder(h = thickness, r = inner);\n    }\n}\n";
    // Unfinished: the call has no `)` and the file ends.
    let items = complete(&format!("{program}washer(ou|"));
    assert_eq!(labels(&items), ["outer ="]);
    let outer = &items[0];
    assert_eq!(outer.insert_text.as_deref(), Some("outer = "));
    assert_eq!(outer.detail.as_deref(), Some("default 10"));
    let doc = outer.doc.as_deref().unwrap_or_default();
    assert!(
        doc.contains("module washer(outer = 10, inner, thickness = 1)")
            && doc.contains("`outer`: the outer radius")
            && !doc.contains("hole"),
        "{doc}"
    );
    let closed = complete(&format!("{program}washer(|);\n"));
    assert_ranked(&closed);
    assert_eq!(parameters(&closed), ["outer =", "inner =", "thickness ="]);
    assert_eq!(item(&closed, "inner =").detail.as_deref(), Some("required"));
}

#[test]
fn user_module_shadowing_a_builtin_offers_its_own_parameters() {
    let items = complete("module sphere(size) cube(size);\nsphere(|);\n");
    assert_eq!(parameters(&items), ["size ="]);
}

#[test]
fn user_function_and_function_literal_offer_their_parameters() {
    let function = "/// Scales `p`.\nfunction grow(p, by = [1, 2]) = p * by[0];\n";
    let items = complete(&format!("{function}x = grow(|);\n"));
    assert_eq!(parameters(&items), ["p =", "by ="]);
    assert_eq!(
        item(&items, "by =").detail.as_deref(),
        Some("default [1, 2]")
    );
    // Special variables reach user functions too.
    assert!(argument_names(&items).contains(&"$t ="));
    let unfinished = complete(&format!("{function}x = 1 + grow(2, |"));
    assert_eq!(parameters(&unfinished), ["by ="]);

    let literal = "add = function(a, b = 2) a + b;\n";
    assert_eq!(
        parameters(&complete(&format!("{literal}x = add(|);\n"))),
        ["a =", "b ="]
    );
    assert_eq!(
        parameters(&complete(&format!("{literal}x = add(|"))),
        ["a =", "b ="]
    );
    // After `)` in a list comprehension the tokens look like a statement; the name is a
    // function all the same.
    assert_eq!(
        parameters(&complete(&format!(
            "{literal}v = [for (i = [0 : 2]) add(i, |"
        ))),
        ["b ="]
    );
}

#[test]
fn definitions_of_used_and_included_files_offer_their_parameters() {
    for head in ["use <lib.scad>\n", "include <lib.scad>\n"] {
        let items = complete(&format!("{head}part(|);\n"));
        assert_eq!(parameters(&items), ["size =", "hollow ="], "{head}");
        let size = item(&items, "size =");
        assert_eq!(size.detail.as_deref(), Some("default 2"));
        let doc = size.doc.as_deref().unwrap_or_default();
        assert!(doc.contains("`size`: the edge length"), "{doc}");

        let unfinished = complete(&format!("{head}part(size = 3, |"));
        assert_eq!(parameters(&unfinished), ["hollow ="], "{head}");
        assert_eq!(
            parameters(&complete(&format!("{head}x = lib_twice(|"))),
            ["x ="],
            "{head}"
        );
    }
}

#[test]
fn names_given_by_name_or_by_position_are_skipped() {
    assert_eq!(parameters(&complete("sphere(r = 1, |);\n")), ["d ="]);
    assert_eq!(
        parameters(&complete("cylinder(10, |, r = 2);\n")),
        ["r1 =", "r2 =", "center =", "d =", "d1 =", "d2 ="]
    );
    // Positional arguments fill only the parameters that may be given by position.
    assert_eq!(parameters(&complete("sphere(1, |);\n")), ["d ="]);
    let cube = complete("cube($fn = 8, |);\n");
    let names = argument_names(&cube);
    assert!(
        !names.contains(&"$fn =") && names.contains(&"$fa =") && names.contains(&"size ="),
        "{names:?}"
    );
    // Every argument is given: only special variables are left.
    assert_eq!(
        parameters(&complete("translate([1, 2, 3], |)\n")),
        Vec::<&str>::new()
    );
}

#[test]
fn values_get_expressions_only() {
    for marked in [
        "sphere(r = |);\n",
        "sphere(r = |",
        "sphere(r = 1 + |);\n",
        "sphere(r = PI * |",
        "translate([1, |]) cube();\n",
        "translate([|",
        "cube(size = [1, 2, |",
        "// sphere(|\n",
        "echo(\"sphere(|\");\n",
    ] {
        let items = complete(marked);
        assert_eq!(argument_names(&items), Vec::<&str>::new(), "{marked}");
    }
    let items = complete("sphere(r = |);\n");
    assert!(labels(&items).contains(&"PI") && !labels(&items).contains(&"cube"));
    // Editing the name of a named argument offers no second `=`.
    assert_eq!(
        argument_names(&complete("sphere(r| = 1);\n")),
        Vec::<&str>::new()
    );
}

#[test]
fn unfinished_text_still_offers_argument_names() {
    // The parser makes an error node of each of these; the tokens still hold the call.
    assert_eq!(parameters(&complete("sphere(r|")), ["r ="]);
    assert_eq!(parameters(&complete("sphere(|")), ["r =", "d ="]);
    assert_eq!(parameters(&complete("sphere(r|\ncube(2);\n")), ["r ="]);
    assert_eq!(
        parameters(&complete("translate([1, 2, 3]) cylinder(h = 2, |")),
        ["r1 =", "r2 =", "center =", "r =", "d =", "d1 =", "d2 ="]
    );
    assert_eq!(
        parameters(&complete("module m(a, b) cube(a);\nif (true) !m(|")),
        ["a =", "b ="]
    );
    let unfinished = complete("translate([1,2,3], |");
    let translate = argument_names(&unfinished);
    assert!(
        !translate.contains(&"v =") && translate.contains(&"$fn ="),
        "{translate:?}"
    );
    // Inside a module's body between finished statements, and with `;` in strings around.
    assert_eq!(
        parameters(&complete(
            "a = \"x;}\";\nmodule m() {\n    cube(1);\n    cylinder(h = 1, r1 = 2, |\n}\nb = \"{\";\n"
        )),
        ["r2 =", "center =", "r =", "d =", "d1 =", "d2 ="]
    );
    // Nested calls: the innermost one around the cursor.
    assert_eq!(
        parameters(&complete(
            "translate([0, 0, 1]) rotate(a = 90) sphere(d = 2, |"
        )),
        ["r ="]
    );
    assert_eq!(
        parameters(&complete("function f(k) = k;\nsphere(r = f(|")),
        ["k ="]
    );
}

/// After a character wider than one byte (an accent in a comment, an emoji, the replacement
/// character of invalid UTF-8) the name being typed starts on a character boundary.
#[test]
fn completion_after_wide_characters() {
    for marked in [
        "// é|",
        "x = 1; // 😀|\n",
        "\u{FFFD}|",
        "// é\nsph|",
        "sphere(r = 1) é|",
    ] {
        let items = complete(marked);
        assert!(!items.is_empty(), "{marked:?}");
    }
    assert!(labels(&complete("// é\nsph|")).contains(&"sphere"));
}
