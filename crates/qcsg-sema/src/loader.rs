//! Loading the files a program pulls in with `include <…>` and `use <…>`.
//!
//! Every file is read and parsed once, however often it is included or used. A path resolves
//! relative to the directory of the file that names it, then relative to each directory of the
//! search path (`QCSG_PATH`), as OpenSCAD does. Files are identified by their lexically normalised
//! path, because the loader may serve editor buffers that do not exist on disk.
//!
//! A file that exists but cannot serve as a source (a device, a directory, a file over the size
//! limit, one that cannot be read) is reported as such at the `<path>`, not as missing; a file that
//! is not valid UTF-8 is reported once, at its first invalid byte, and checked as decoded.

use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};

use qcsg_diag::{Diagnostic, FileId, SourceMap, Span};
use qcsg_syntax::ast::{SourceFile, Stmt, StmtKind};

use crate::read::{InvalidUtf8, SourceError, describe};
use crate::{CheckOptions, FileLoader, codes};

/// The name under which standard input is checked; its includes resolve from the current
/// directory.
pub const STDIN_NAME: &str = "<stdin>";

/// Whether an edge is an `include` or a `use`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LinkKind {
    /// `include <…>`: everything of the file, spliced in place.
    Include,
    /// `use <…>`: the file's modules and functions only.
    Use,
}

/// One `include <…>` or `use <…>` statement and the file it resolved to.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FileLink {
    /// Include or use.
    pub kind: LinkKind,
    /// The file the statement is in.
    pub file: FileId,
    /// The span of `<path>`.
    pub span: Span,
    /// The file it names, or `None` when it was not found.
    pub target: Option<FileId>,
}

/// A `use <file.ttf>` (or `.otf`): as in OpenSCAD 2021.01, a font file named by `use` is not a
/// library but registers its faces for `text(font = …)`. The checker only finds the file; the
/// evaluator reads it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FontUse {
    /// The file the statement is in.
    pub file: FileId,
    /// The span of `<path>`.
    pub span: Span,
    /// The font file found.
    pub path: PathBuf,
}

/// Whether `use <path>` names a font file: its extension is `.ttf` or `.otf`, in any case, as
/// OpenSCAD tells them.
pub fn is_font_path(path: &str) -> bool {
    Path::new(path).extension().is_some_and(|e| {
        let e = e.to_string_lossy();
        e.eq_ignore_ascii_case("ttf") || e.eq_ignore_ascii_case("otf")
    })
}

/// Every file of a program, parsed, with the links between them.
pub(crate) struct Loaded {
    /// The font files named by `use`, in the order found.
    pub fonts: Vec<FontUse>,
    /// The tree of each file, indexed by `FileId`.
    pub trees: Vec<SourceFile>,
    /// Where each `include` / `use` leads, keyed by (file, start of the `<path>` span).
    pub links: HashMap<(FileId, u32), FileLink>,
    /// Links in the order they were found.
    pub link_list: Vec<FileLink>,
    /// Indices into `link_list` of each file's links.
    pub links_by_file: HashMap<FileId, Vec<usize>>,
}

impl Loaded {
    /// The file an include or use at `span` of `file` resolved to.
    pub fn target(&self, file: FileId, span: Span) -> Option<FileId> {
        self.links
            .get(&(file, span.start))
            .and_then(|link| link.target)
    }

    /// The `include` / `use` statements of `file`, in source order.
    pub fn links_of(&self, file: FileId) -> impl Iterator<Item = &FileLink> {
        self.links_by_file
            .get(&file)
            .into_iter()
            .flatten()
            .filter_map(|&i| self.link_list.get(i))
    }

    /// The tree of `file`.
    pub fn tree(&self, file: FileId) -> Option<&SourceFile> {
        self.trees.get(file.0 as usize)
    }
}

/// Removes `.` components and folds `..` into its parent where there is one.
pub(crate) fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for component in path.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir => {
                let last_is_normal =
                    matches!(out.components().next_back(), Some(Component::Normal(_)));
                if last_is_normal {
                    out.pop();
                } else if !matches!(
                    out.components().next_back(),
                    Some(Component::RootDir | Component::Prefix(_))
                ) {
                    out.push("..");
                }
            }
            other => out.push(other.as_os_str()),
        }
    }
    if out.as_os_str().is_empty() {
        PathBuf::from(".")
    } else {
        out
    }
}

/// The directory `include`s of a file resolve from.
fn base_dir(name: &str) -> PathBuf {
    if name == STDIN_NAME {
        return PathBuf::from(".");
    }
    match Path::new(name).parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Every `include` / `use` statement of a tree, in source order, found without recursion.
fn link_statements(tree: &SourceFile) -> Vec<(LinkKind, &qcsg_syntax::ast::PathLit)> {
    let mut found = Vec::new();
    let mut stack: Vec<&Stmt> = tree.stmts.iter().rev().collect();
    while let Some(stmt) = stack.pop() {
        match &stmt.kind {
            StmtKind::Include(path) => found.push((LinkKind::Include, path)),
            StmtKind::Use(path) => found.push((LinkKind::Use, path)),
            StmtKind::Block(stmts) => stack.extend(stmts.iter().rev()),
            StmtKind::ModuleDef { body, .. }
            | StmtKind::For { body, .. }
            | StmtKind::Let { body, .. }
            | StmtKind::Modified { body, .. } => stack.push(body),
            StmtKind::If { then, els, .. } => {
                if let Some(els) = els {
                    stack.push(els);
                }
                stack.push(then);
            }
            StmtKind::Instantiate {
                child: Some(child), ..
            } => stack.push(child),
            _ => {}
        }
    }
    found
}

/// Why an `include` / `use` found no file to load.
enum LinkError {
    /// No candidate exists; these are the places searched.
    NotFound(Vec<PathBuf>),
    /// The candidate at `path` exists but cannot be loaded.
    Unreadable { path: PathBuf, error: SourceError },
}

/// Parses `main` (whose text has `main_invalid_utf8`, if it was not valid UTF-8) and loads, parses
/// and links everything it includes or uses, transitively.
pub(crate) fn load_program(
    sources: &mut SourceMap,
    main: FileId,
    main_invalid_utf8: Option<InvalidUtf8>,
    options: &CheckOptions,
    loader: &dyn FileLoader,
    diagnostics: &mut Vec<Diagnostic>,
) -> Loaded {
    let mut loaded = Loaded {
        fonts: Vec::new(),
        trees: Vec::new(),
        links: HashMap::new(),
        link_list: Vec::new(),
        links_by_file: HashMap::new(),
    };
    let mut by_path: HashMap<PathBuf, FileId> = HashMap::new();
    let mut invalid_utf8: HashMap<FileId, InvalidUtf8> = HashMap::new();
    if let Some(invalid) = main_invalid_utf8 {
        invalid_utf8.insert(main, invalid);
    }
    let main_name = sources.get(main).name.clone();
    if main_name != STDIN_NAME {
        by_path.insert(normalize(Path::new(&main_name)), main);
    }
    let mut next = main.0 as usize;
    let mut file_count = next + 1;
    // Files are added to the source map in discovery order, so walking ids is a breadth-first
    // traversal that parses each file exactly once.
    while next < file_count {
        let file = FileId(next as u32);
        next += 1;
        let source = sources.get(file);
        let dialect = qcsg_syntax::Dialect::of_file(&source.name);
        let parse = qcsg_syntax::parse_as(&source.text, file, dialect);
        match invalid_utf8.get(&file) {
            Some(invalid) => {
                diagnostics.push(invalid_utf8_diagnostic(file, invalid));
                let text = &sources.get(file).text;
                diagnostics.extend(
                    parse
                        .diagnostics
                        .into_iter()
                        .filter(|d| !is_replacement_only(text, d)),
                );
            }
            None => diagnostics.extend(parse.diagnostics),
        }
        let tree = parse.file;
        let dir = base_dir(&sources.get(file).name);
        for (kind, path) in link_statements(&tree) {
            if kind == LinkKind::Use && is_font_path(&path.path) {
                match find_font_file(&dir, &path.path, options) {
                    Ok(found) => loaded.fonts.push(FontUse {
                        file,
                        span: path.span,
                        path: found,
                    }),
                    Err(error) => diagnostics.push(error.diagnostic(&path.path, file, path.span)),
                }
                continue;
            }
            let keyword = if kind == LinkKind::Include {
                "include"
            } else {
                "use"
            };
            let target = resolve_link(
                sources,
                &mut by_path,
                &mut invalid_utf8,
                &dir,
                &path.path,
                options,
                loader,
            );
            let target = match target {
                Ok(target) => {
                    file_count = file_count.max(target.0 as usize + 1);
                    Some(target)
                }
                Err(LinkError::Unreadable { path: found, error }) => {
                    let code = match error {
                        SourceError::NotAFile { .. } => codes::NOT_A_FILE,
                        SourceError::TooLarge { .. } => codes::FILE_TOO_LARGE,
                        _ => codes::UNREADABLE_FILE,
                    };
                    diagnostics.push(Diagnostic::error(
                        code,
                        format!(
                            "cannot read `{}` named by `{keyword}`: {error}",
                            found.display()
                        ),
                        file,
                        path.span,
                    ));
                    None
                }
                Err(LinkError::NotFound(searched)) => {
                    let help = format!(
                        "searched {}; set QCSG_PATH to add library directories",
                        searched
                            .iter()
                            .map(|p| format!("`{}`", p.display()))
                            .collect::<Vec<_>>()
                            .join(", ")
                    );
                    diagnostics.push(
                        Diagnostic::error(
                            codes::FILE_NOT_FOUND,
                            format!("cannot find `{}` named by `{keyword}`", path.path),
                            file,
                            path.span,
                        )
                        .with_help(help),
                    );
                    None
                }
            };
            let link = FileLink {
                kind,
                file,
                span: path.span,
                target,
            };
            loaded.links.insert((file, path.span.start), link.clone());
            loaded
                .links_by_file
                .entry(file)
                .or_default()
                .push(loaded.link_list.len());
            loaded.link_list.push(link);
        }
        if loaded.trees.len() <= file.0 as usize {
            loaded
                .trees
                .resize_with(file.0 as usize + 1, || SourceFile {
                    stmts: Vec::new(),
                    comments: Vec::new(),
                });
        }
        loaded.trees[file.0 as usize] = tree;
    }
    loaded
}

/// The error for a file that is not valid UTF-8, at its first invalid sequence.
fn invalid_utf8_diagnostic(file: FileId, invalid: &InvalidUtf8) -> Diagnostic {
    Diagnostic::error(
        codes::INVALID_UTF8,
        format!("not valid UTF-8: {}", describe(invalid)),
        file,
        invalid.span,
    )
    .with_help(
        "source files are UTF-8: save the file in that encoding (until then, each invalid \
         sequence reads as U+FFFD)",
    )
}

/// Whether `diagnostic` is the lexer's "invalid character" for replacement characters only,
/// which the invalid-UTF-8 error of the file already covers.
fn is_replacement_only(text: &str, diagnostic: &Diagnostic) -> bool {
    diagnostic.code == qcsg_syntax::codes::INVALID_CHARACTER
        && text
            .get(diagnostic.span.range())
            .is_some_and(|s| !s.is_empty() && s.chars().all(|c| c == '\u{FFFD}'))
}

/// Finds and loads the file `path` names; on failure, the places searched or why the file found
/// cannot be loaded.
fn resolve_link(
    sources: &mut SourceMap,
    by_path: &mut HashMap<PathBuf, FileId>,
    invalid_utf8: &mut HashMap<FileId, InvalidUtf8>,
    dir: &Path,
    path: &str,
    options: &CheckOptions,
    loader: &dyn FileLoader,
) -> Result<FileId, LinkError> {
    let candidates = candidates(dir, path, options);
    for candidate in &candidates {
        if let Some(&known) = by_path.get(candidate) {
            return Ok(known);
        }
        let (text, invalid) = match loader.load(candidate).map_err(SourceError::from_io) {
            Ok(text) => (text, None),
            Err(SourceError::InvalidUtf8(source)) => (source.text, source.invalid_utf8),
            Err(error) if error.is_not_found() => continue,
            Err(error) => {
                return Err(LinkError::Unreadable {
                    path: candidate.clone(),
                    error,
                });
            }
        };
        let id = sources.add(candidate.to_string_lossy().into_owned(), text);
        by_path.insert(candidate.clone(), id);
        if let Some(invalid) = invalid {
            invalid_utf8.insert(id, invalid);
        }
        return Ok(id);
    }
    Err(LinkError::NotFound(candidates))
}

/// The places a link's `path` may name: relative to `dir`, then to each search directory.
fn candidates(dir: &Path, path: &str, options: &CheckOptions) -> Vec<PathBuf> {
    let written = Path::new(path);
    if path.is_empty() {
        Vec::new()
    } else if written.is_absolute() {
        vec![normalize(written)]
    } else {
        std::iter::once(dir)
            .chain(options.search_path.iter().map(PathBuf::as_path))
            .map(|base| normalize(&base.join(written)))
            .collect()
    }
}

/// Why a font file named by `use` was not found.
enum FontFileError {
    /// No candidate exists; these are the places searched.
    NotFound(Vec<PathBuf>),
    /// The candidate exists but is not a regular file.
    NotAFile(PathBuf),
}

impl FontFileError {
    fn diagnostic(&self, written: &str, file: FileId, span: Span) -> Diagnostic {
        match self {
            Self::NotFound(searched) => Diagnostic::error(
                codes::FILE_NOT_FOUND,
                format!("cannot find the font file `{written}` named by `use`"),
                file,
                span,
            )
            .with_help(format!(
                "searched {}; set QCSG_PATH to add library directories",
                searched
                    .iter()
                    .map(|p| format!("`{}`", p.display()))
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
            Self::NotAFile(path) => Diagnostic::error(
                codes::NOT_A_FILE,
                format!(
                    "cannot read the font `{}` named by `use`: it is not a regular file",
                    path.display()
                ),
                file,
                span,
            ),
        }
    }
}

/// The font file `path` names, looked for where a library would be.
fn find_font_file(
    dir: &Path,
    path: &str,
    options: &CheckOptions,
) -> Result<PathBuf, FontFileError> {
    let candidates = candidates(dir, path, options);
    for candidate in &candidates {
        match std::fs::metadata(candidate) {
            Ok(meta) if meta.is_file() => return Ok(candidate.clone()),
            Ok(_) => return Err(FontFileError::NotAFile(candidate.clone())),
            Err(_) => continue,
        }
    }
    Err(FontFileError::NotFound(candidates))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalize_folds_dots() {
        assert_eq!(
            normalize(Path::new("a/./b/../c.scad")),
            PathBuf::from("a/c.scad")
        );
        assert_eq!(normalize(Path::new("../x/../y")), PathBuf::from("../y"));
        assert_eq!(normalize(Path::new("/a/../../b")), PathBuf::from("/b"));
        assert_eq!(normalize(Path::new("./")), PathBuf::from("."));
    }

    #[test]
    fn base_dir_of_stdin_is_current() {
        assert_eq!(base_dir(STDIN_NAME), PathBuf::from("."));
        assert_eq!(base_dir("main.scad"), PathBuf::from("."));
        assert_eq!(base_dir("dir/main.scad"), PathBuf::from("dir"));
    }
}
