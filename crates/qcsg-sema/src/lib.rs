//! Name resolution, include/use loading and static checking of qcsg programs (docs/language.md,
//! "Static checking").
//!
//! [`check_file`] is the entry point: it parses the main file, loads what it includes or uses
//! through a [`FileLoader`], resolves every name and reports static errors and warnings. The
//! [`Analysis`] it returns also records what it resolved — every definition and, for every name
//! reference, the definition it resolves to — as plain data for the evaluator and the language
//! server (hover, go-to-definition, references, rename).
//!
//! Decisions where OpenSCAD is lenient:
//! - Extra positional arguments (to built-ins and to user modules and functions) are errors
//!   ([`codes::TOO_MANY_ARGUMENTS`]): OpenSCAD ignores them, so they are certainly a mistake.
//! - A user parameter without a default that a call does not supply is an error
//!   ([`codes::MISSING_ARGUMENT`]): it would be `undef`. Write `p = undef` to make it optional; a
//!   parameter the body tests for `undef` (`is_undef(p)`, `p == undef`, `is_num(p)`, …) is
//!   optional too, as that is how OpenSCAD code spells it.
//! - `$`-arguments (`$fn = 32`, `$my = 1`) are accepted by every module and function call.
//! - A variable read by an assignment before its own assignment in the same scope is an error
//!   ([`codes::USED_BEFORE_ASSIGNMENT`]) unless an enclosing scope defines it, which is what
//!   OpenSCAD then reads.
//! - Overriding a variable of an included file after the `include` is not a reassignment warning
//!   (the customary way to configure a library), as in OpenSCAD.
//! - Named arguments to built-in *functions* are errors ([`codes::UNKNOWN_ARGUMENT`]): OpenSCAD
//!   ignores the names and matches by position, so `atan2(x = 1, y = 2)` is `atan2(1, 2)`.
//! - Parameter defaults are resolved in the scope of the definition, as OpenSCAD evaluates them:
//!   `module m(a, b = a)` reads an outer `a`, never the parameter.
//! - Unused-name warnings cover the main file only (a library offers more than any one file
//!   uses) and never loop variables (`for (i = [0 : 3]) cube(1);` repeats on purpose), `$`-names
//!   or names starting with `_`.
//! - Type errors are reported only where the known types make the operation fail whatever the
//!   unknown parts turn out to be ([`Ty::Any`] alone never errs); parameters are of unknown type,
//!   and so is a variable overridden with `-D`.

pub mod builtins;
pub mod codes;
mod fxhash;
mod loader;
mod read;
mod resolve;
mod suggest;
pub mod ty;

use std::path::{Path, PathBuf};

use qcsg_diag::{Diagnostic, FileId, SourceMap, Span};

pub use loader::{FileLink, FontUse, LinkKind, STDIN_NAME, is_font_path};
pub use read::{
    InvalidUtf8, MAX_SOURCE_BYTES, SourceError, SourceText, load_source, read_bytes_with_limit,
    read_source, read_source_from, read_source_with_limit,
};
pub use ty::Ty;

/// Reads files for `include` / `use`; the CLI reads the file system, the language server also
/// sees unsaved editor buffers.
pub trait FileLoader {
    /// The text of the file at `path`. A loader that reads files should read them with
    /// [`load_source`], whose errors say what is wrong (a device, too large, not UTF-8) in a way
    /// the checker reports at the `include`.
    fn load(&self, path: &Path) -> std::io::Result<String>;
}

/// A [`FileLoader`] reading the file system with [`load_source`].
#[derive(Clone, Copy, Debug, Default)]
pub struct FsLoader;

impl FileLoader for FsLoader {
    fn load(&self, path: &Path) -> std::io::Result<String> {
        load_source(path)
    }
}

/// Settings of a check.
#[derive(Clone, Debug, Default)]
pub struct CheckOptions {
    /// Directories searched for `include <…>` / `use <…>` after the including file's directory
    /// (from `QCSG_PATH`).
    pub search_path: Vec<PathBuf>,
    /// `-D name=value` overrides of top-level variables, value as source text.
    pub defines: Vec<(String, String)>,
}

/// Handle of a [`Definition`] in [`Analysis::definitions`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct DefId(pub u32);

/// What a definition defines.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DefKind {
    /// `name = value;`
    Variable,
    /// A parameter of a module, function or function literal.
    Parameter,
    /// A `for` variable (statement, comprehension or `intersection_for`).
    LoopVariable,
    /// A `let` variable.
    LetVariable,
    /// `module name(…) …`
    Module,
    /// `function name(…) = …;`
    Function,
}

/// A parameter of a module, function or function-literal variable.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamInfo {
    /// Its name.
    pub name: String,
    /// The span of the name.
    pub name_span: Span,
    /// The whole parameter, default included.
    pub span: Span,
    /// Whether it has a default value.
    pub has_default: bool,
    /// Whether the body tests it for `undef` (`is_undef(p)`, `p == undef`, `is_num(p)`, …), which
    /// makes it optional even without a default.
    pub tested_for_undef: bool,
    /// Its own definition (references to the parameter resolve to it).
    pub def: DefId,
}

/// A name introduced in the source.
#[derive(Clone, Debug, PartialEq)]
pub struct Definition {
    /// What it defines.
    pub kind: DefKind,
    /// The name.
    pub name: String,
    /// The file it is written in.
    pub file: FileId,
    /// The span of the name.
    pub name_span: Span,
    /// The whole definition (statement, binding or parameter).
    pub span: Span,
    /// Its doc comment, markers stripped.
    pub doc: Option<String>,
    /// Parameters of modules, functions and variables holding a function literal.
    pub params: Option<Vec<ParamInfo>>,
    /// The module, function or function-literal variable it belongs to.
    pub parent: Option<DefId>,
    /// For a reassignment, the earlier assignment of the same variable in the same scope.
    pub redefines: Option<DefId>,
    /// The statically inferred type of a variable's value, or of a function's result
    /// ([`Ty::Any`] when unknown).
    pub ty: Ty,
}

/// The namespace a reference looks a name up in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Namespace {
    /// Variables (parameters, loop and `let` variables included).
    Variable,
    /// Functions.
    Function,
    /// Modules.
    Module,
}

/// What a reference resolves to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Target {
    /// A definition in the source.
    Definition(DefId),
    /// A built-in ([`builtins`]), looked up by the reference's name and namespace.
    Builtin,
    /// A variable given on the command line (`-D name=value`).
    CommandLine,
}

/// A use of a name that resolved.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Reference {
    /// The file it is in.
    pub file: FileId,
    /// The span of the name.
    pub span: Span,
    /// The namespace it was looked up in.
    pub namespace: Namespace,
    /// What it resolves to.
    pub target: Target,
}

/// The result of checking one program.
#[derive(Debug)]
pub struct Analysis {
    /// The main file and every file it pulled in.
    pub sources: SourceMap,
    /// The main file.
    pub main: FileId,
    /// Every diagnostic of every file, sorted by [`qcsg_diag::sort_diagnostics`].
    pub diagnostics: Vec<Diagnostic>,
    /// The syntax tree of every file, indexed by [`FileId`].
    pub trees: Vec<qcsg_syntax::SourceFile>,
    /// Every `include` / `use` statement and the file it resolved to.
    pub links: Vec<FileLink>,
    /// The font files named by `use <file.ttf>`, found; the evaluator registers their faces.
    pub fonts: Vec<FontUse>,
    /// Every definition, indexed by [`DefId`].
    pub definitions: Vec<Definition>,
    /// Every resolved name reference (a definition's own name is not a reference).
    pub references: Vec<Reference>,
}

impl Analysis {
    /// The definition behind a handle.
    pub fn definition(&self, id: DefId) -> Option<&Definition> {
        self.definitions.get(id.0 as usize)
    }

    /// The syntax tree of a file.
    pub fn tree(&self, file: FileId) -> Option<&qcsg_syntax::SourceFile> {
        self.trees.get(file.0 as usize)
    }

    /// Whether the program has errors.
    pub fn has_errors(&self) -> bool {
        self.diagnostics.iter().any(Diagnostic::is_error)
    }

    /// The reference whose name covers byte `offset` of `file`.
    pub fn reference_at(&self, file: FileId, offset: usize) -> Option<&Reference> {
        self.references
            .iter()
            .find(|r| r.file == file && r.span.contains(offset))
    }

    /// The definition whose name covers byte `offset` of `file`.
    pub fn definition_at(&self, file: FileId, offset: usize) -> Option<(DefId, &Definition)> {
        self.definitions
            .iter()
            .enumerate()
            .find(|(_, d)| d.file == file && d.name_span.contains(offset))
            .map(|(i, d)| (DefId(i as u32), d))
    }

    /// Every reference to a definition, in creation order.
    pub fn references_to(&self, id: DefId) -> impl Iterator<Item = &Reference> {
        self.references
            .iter()
            .filter(move |r| r.target == Target::Definition(id))
    }
}

/// Checks the program whose main file is `name` (a path, or `<stdin>`) with contents `text`.
pub fn check_file(
    name: &str,
    text: String,
    options: &CheckOptions,
    loader: &dyn FileLoader,
) -> Analysis {
    check_source(name, text.into(), options, loader)
}

/// [`check_file`] for a main file read by [`read_source`]: invalid UTF-8 in it is reported as
/// in any included file.
pub fn check_source(
    name: &str,
    source: SourceText,
    options: &CheckOptions,
    loader: &dyn FileLoader,
) -> Analysis {
    let mut sources = SourceMap::new();
    let main = sources.add(name, source.text);
    let mut diagnostics = Vec::new();
    let loaded = loader::load_program(
        &mut sources,
        main,
        source.invalid_utf8,
        options,
        loader,
        &mut diagnostics,
    );
    let defines = options.defines.iter().map(|(name, _)| name.clone());
    let resolved = resolve::Resolver::new(&loaded, &sources, main, defines).run();
    diagnostics.extend(resolved.diagnostics);
    qcsg_diag::sort_diagnostics(&mut diagnostics);
    diagnostics.dedup();
    let loader::Loaded {
        trees,
        link_list,
        fonts,
        ..
    } = loaded;
    Analysis {
        sources,
        main,
        diagnostics,
        trees,
        links: link_list,
        fonts,
        definitions: resolved.definitions,
        references: resolved.references,
    }
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use super::*;

    /// Files served from memory, as the language server serves editor buffers.
    #[derive(Default)]
    struct MemoryLoader(HashMap<PathBuf, String>);

    impl MemoryLoader {
        fn with(mut self, path: &str, text: &str) -> Self {
            self.0.insert(PathBuf::from(path), text.to_string());
            self
        }
    }

    impl FileLoader for MemoryLoader {
        fn load(&self, path: &Path) -> std::io::Result<String> {
            self.0
                .get(path)
                .cloned()
                .ok_or_else(|| std::io::ErrorKind::NotFound.into())
        }
    }

    fn check(text: &str) -> Analysis {
        check_with(text, &CheckOptions::default(), &MemoryLoader::default())
    }

    fn check_with(text: &str, options: &CheckOptions, loader: &MemoryLoader) -> Analysis {
        check_file("dir/main.scad", text.to_string(), options, loader)
    }

    fn codes(analysis: &Analysis) -> Vec<&'static str> {
        analysis.diagnostics.iter().map(|d| d.code).collect()
    }

    fn offset_of(text: &str, needle: &str, nth: usize) -> usize {
        text.match_indices(needle)
            .nth(nth)
            .map(|(i, _)| i)
            .expect("needle present")
    }

    #[test]
    fn references_resolve_to_their_definitions() {
        let text = "module m(size) cube(size);\nfunction f(x) = x + 1;\nv = f(2);\nm(size = v);\n";
        let analysis = check(text);
        assert!(
            analysis.diagnostics.is_empty(),
            "{:?}",
            analysis.diagnostics
        );
        let target = |needle: &str, nth: usize| {
            let reference = analysis
                .reference_at(analysis.main, offset_of(text, needle, nth))
                .expect("reference");
            match reference.target {
                Target::Definition(id) => analysis.definition(id).map(|d| (d.kind, d.name.clone())),
                _ => None,
            }
        };
        assert_eq!(target("f(", 1), Some((DefKind::Function, "f".into())));
        assert_eq!(target("m(", 1), Some((DefKind::Module, "m".into())));
        assert_eq!(target("v)", 0), Some((DefKind::Variable, "v".into())));
        // A named argument refers to the parameter it sets; the parameter's use in the body too.
        assert_eq!(
            target("size =", 0),
            Some((DefKind::Parameter, "size".into()))
        );
        assert_eq!(
            target("size)", 1),
            Some((DefKind::Parameter, "size".into()))
        );
        let cube = analysis
            .reference_at(analysis.main, offset_of(text, "cube", 0))
            .expect("cube");
        assert_eq!(
            (cube.target, cube.namespace),
            (Target::Builtin, Namespace::Module)
        );
        let (module_id, module) = analysis
            .definition_at(analysis.main, offset_of(text, "m(", 0))
            .expect("m");
        assert_eq!(module.params.as_ref().map(Vec::len), Some(1));
        assert_eq!(analysis.references_to(module_id).count(), 1);
    }

    #[test]
    fn doc_comments_and_types_are_recorded() {
        let text = "/// The width.\nwidth = [1, 2, 3];\ncube(width);\n";
        let analysis = check(text);
        let (_, width) = analysis
            .definition_at(analysis.main, offset_of(text, "width", 1))
            .expect("width");
        assert_eq!(width.doc.as_deref(), Some("The width."));
        assert_eq!(width.ty, Ty::number_vector(Some(3)));
    }

    #[test]
    fn includes_resolve_from_the_file_then_the_search_path() {
        let loader = MemoryLoader::default()
            .with("dir/near.scad", "near = 1;\n")
            .with("libs/far.scad", "module far() cube(1);\nfar_value = 2;\n");
        let options = CheckOptions {
            search_path: vec![PathBuf::from("libs")],
            defines: Vec::new(),
        };
        let analysis = check_with(
            "include <near.scad>\nuse <far.scad>\nfar();\necho(near);\n",
            &options,
            &loader,
        );
        assert!(
            analysis.diagnostics.is_empty(),
            "{:?}",
            analysis.diagnostics
        );
        assert_eq!(analysis.links.len(), 2);
        assert!(analysis.links.iter().all(|link| link.target.is_some()));
        assert!(analysis.sources.find("libs/far.scad").is_some());
    }

    #[test]
    fn missing_include_lists_the_places_searched() {
        let options = CheckOptions {
            search_path: vec![PathBuf::from("libs")],
            defines: Vec::new(),
        };
        let analysis = check_with("include <gone.scad>\n", &options, &MemoryLoader::default());
        assert_eq!(codes(&analysis), [codes::FILE_NOT_FOUND]);
        let help = analysis.diagnostics[0].help.clone().unwrap_or_default();
        assert!(
            help.contains("dir/gone.scad") && help.contains("libs/gone.scad"),
            "{help}"
        );
    }

    #[test]
    fn stdin_includes_resolve_from_the_current_directory() {
        let loader = MemoryLoader::default().with("parts.scad", "module part() cube(1);\n");
        let analysis = check_file(
            STDIN_NAME,
            "include <parts.scad>\npart();\n".into(),
            &CheckOptions::default(),
            &loader,
        );
        assert!(
            analysis.diagnostics.is_empty(),
            "{:?}",
            analysis.diagnostics
        );
    }

    #[test]
    fn include_cycles_are_reported_once_with_the_other_include() {
        let loader = MemoryLoader::default()
            .with("dir/a.scad", "include <b.scad>\n")
            .with("dir/b.scad", "include <a.scad>\n");
        let analysis = check_with("include <a.scad>\n", &CheckOptions::default(), &loader);
        assert_eq!(codes(&analysis), [codes::INCLUDE_CYCLE]);
        let cycle = &analysis.diagnostics[0];
        assert_eq!(analysis.sources.get(cycle.file).name, "dir/b.scad");
        assert_eq!(cycle.labels.len(), 1);
        assert_eq!(cycle.labels[0].file, analysis.main);
    }

    #[test]
    fn defines_make_values_unknown_and_names_defined() {
        let options = CheckOptions {
            search_path: Vec::new(),
            defines: vec![
                ("size".into(), "\"big\"".into()),
                ("extra".into(), "1".into()),
            ],
        };
        // `size` might be anything once overridden, and `extra` exists only on the command line.
        let analysis = check_with(
            "size = 1;\ncube(size + extra);\n",
            &options,
            &MemoryLoader::default(),
        );
        assert!(
            analysis.diagnostics.is_empty(),
            "{:?}",
            analysis.diagnostics
        );
    }

    #[test]
    fn deep_nesting_does_not_overflow_the_stack() {
        let depth = 20_000;
        let text = format!(
            "x = {}1{};\necho(x);\n",
            "(".repeat(depth),
            ")".repeat(depth)
        );
        let _ = check(&text);
        let sum = format!("y = 0{};\necho(y);\n", " + 1".repeat(depth));
        // The parser refuses such depth with a diagnostic; the checker must just not crash.
        let _ = check(&sum);
        let chain = format!("z = 0{};\necho(z);\n", " + 1".repeat(900));
        assert!(!check(&chain).has_errors());
        let blocks = format!(
            "{}cube(1);{}\n",
            "translate([1, 0, 0]) {".repeat(2000),
            "}".repeat(2000)
        );
        let _ = check(&blocks);
    }

    #[test]
    fn a_file_included_twice_defines_its_names_once() {
        let loader =
            MemoryLoader::default().with("dir/lib.scad", "size = 2;\nmodule part() cube(size);\n");
        let text = "include <lib.scad>\nsize = 3;\ninclude <lib.scad>\npart();\n";
        let analysis = check_with(text, &CheckOptions::default(), &loader);
        // As in OpenSCAD, the second include overwrites the main file's value, which is unused.
        assert_eq!(
            codes(&analysis),
            [codes::UNUSED_VARIABLE, codes::REASSIGNMENT]
        );
        let sizes: Vec<&Definition> = analysis
            .definitions
            .iter()
            .filter(|d| d.name == "size")
            .collect();
        assert_eq!(sizes.len(), 2);
        // `redefines` chains end.
        for definition in &analysis.definitions {
            let mut steps = 0;
            let mut next = definition.redefines;
            while let Some(id) = next {
                steps += 1;
                assert!(
                    steps <= analysis.definitions.len(),
                    "cyclic redefinition chain"
                );
                next = analysis.definition(id).and_then(|d| d.redefines);
            }
        }
    }

    #[test]
    fn long_include_and_use_chains_do_not_overflow_the_stack() {
        let mut loader = MemoryLoader::default();
        let files = 3000;
        for i in 0..files {
            let used = format!("use <u{}.scad>\nmodule u{i}() cube(1);\n", i + 1);
            let included = format!("include <i{}.scad>\nmodule i{i}() cube(1);\n", i + 1);
            loader = loader
                .with(&format!("dir/u{i}.scad"), &used)
                .with(&format!("dir/i{i}.scad"), &included);
        }
        let analysis = check_with(
            "use <u0.scad>\ninclude <i0.scad>\nu0();\ni0();\n",
            &CheckOptions::default(),
            &loader,
        );
        // Only the two ends of the chains are missing.
        assert!(
            analysis
                .diagnostics
                .iter()
                .all(|d| d.code == codes::FILE_NOT_FOUND),
            "{:?}",
            analysis.diagnostics.first()
        );
    }

    /// A loader whose files fail as [`load_source`] fails on a device or on invalid UTF-8.
    struct FailingLoader;

    impl FileLoader for FailingLoader {
        fn load(&self, path: &Path) -> std::io::Result<String> {
            match path.to_str() {
                Some("dir/device.scad") => Err(SourceError::NotAFile {
                    what: "a character device",
                }
                .into()),
                Some("dir/latin1.scad") => Err(SourceError::InvalidUtf8(SourceText::decode(
                    b"x = \"\xE9\"; // \xFF\xFE\nmodule part() cube(1);\n".to_vec(),
                ))
                .into()),
                Some("dir/locked.scad") => Err(std::io::ErrorKind::PermissionDenied.into()),
                _ => Err(std::io::ErrorKind::NotFound.into()),
            }
        }
    }

    #[test]
    fn files_that_exist_but_cannot_be_loaded_say_why() {
        let options = CheckOptions::default();
        let analysis = check_with(
            "include <device.scad>\nuse <locked.scad>\n",
            &options,
            &MemoryLoader::default(),
        );
        assert_eq!(
            codes(&analysis),
            [codes::FILE_NOT_FOUND, codes::FILE_NOT_FOUND]
        );
        let analysis = check_file(
            "dir/main.scad",
            "include <device.scad>\nuse <locked.scad>\n".into(),
            &options,
            &FailingLoader,
        );
        assert_eq!(
            codes(&analysis),
            [codes::NOT_A_FILE, codes::UNREADABLE_FILE]
        );
        assert_eq!(
            analysis.diagnostics[0].message,
            "cannot read `dir/device.scad` named by `include`: it is a character device, not a \
             regular file"
        );
    }

    #[test]
    fn invalid_utf8_is_one_error_in_its_file_and_the_rest_is_checked() {
        let analysis = check_file(
            "dir/main.scad",
            "include <latin1.scad>\npart();\n".into(),
            &CheckOptions::default(),
            &FailingLoader,
        );
        // One error; `part` is defined after the invalid bytes, and found.
        assert_eq!(
            codes(&analysis),
            [codes::INVALID_UTF8],
            "{:?}",
            analysis.diagnostics
        );
        let error = &analysis.diagnostics[0];
        assert_eq!(analysis.sources.get(error.file).name, "dir/latin1.scad");
        assert_eq!(error.span, Span::new(5, 8));
        assert_eq!(
            error.message,
            "not valid UTF-8: byte 0xE9; 2 more invalid sequences follow"
        );

        // A replacement character outside a string is also an invalid character, which the
        // invalid UTF-8 already says.
        let main = SourceText::decode(b"a = 1;\necho(a, \"\xC3(\");\n\xFF\n".to_vec());
        let analysis = check_source(
            "dir/main.scad",
            main,
            &CheckOptions::default(),
            &MemoryLoader::default(),
        );
        assert_eq!(codes(&analysis), [codes::INVALID_UTF8]);
        assert_eq!(analysis.diagnostics[0].file, analysis.main);
        assert_eq!(analysis.diagnostics[0].span, Span::new(16, 19));
    }

    #[test]
    fn garbage_never_panics() {
        for text in [
            "",
            "(((",
            "module",
            "x = ;",
            "include <",
            "for (i = ) {",
            "f(,,)",
            "a.b.c[1](2)",
            "$",
            "use <>",
        ] {
            let _ = check(text);
        }
    }
}
