//! Go to definition, find references and rename.

use std::collections::{HashMap, HashSet};
use std::fmt;

use qcsg_sema::{DefId, Target};

use crate::{Analysis, FileRange, LineCol, Span, TextRange};

/// The name a rename would change, as `prepareRename` reports it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RenameTarget {
    /// The name under the cursor.
    pub range: TextRange,
    /// Its current text.
    pub name: String,
}

/// Why a rename is refused.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RenameError {
    /// There is no renameable name at the position.
    NoName,
    /// The name is a built-in (or set on the command line), which the program cannot rename.
    Builtin(String),
    /// The new name is not a valid identifier of the same kind.
    InvalidName(String),
}

impl fmt::Display for RenameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RenameError::NoName => f.write_str("there is no name to rename here"),
            RenameError::Builtin(name) => write!(f, "`{name}` is a built-in and cannot be renamed"),
            RenameError::InvalidName(name) => write!(f, "`{name}` is not a valid name here"),
        }
    }
}

impl std::error::Error for RenameError {}

/// What the name under the cursor is.
enum Resolved {
    Definition(DefId),
    Other,
}

const KEYWORDS: &[&str] = &[
    "module", "function", "if", "else", "for", "let", "each", "true", "false", "undef", "include",
    "use", "assert", "echo",
];

impl Analysis {
    /// The name at `offset` of the main document (or just before it) and what it denotes.
    fn resolve_at(&self, offset: usize) -> Option<(Span, Resolved)> {
        let main = self.sema.main;
        for offset in [offset, offset.saturating_sub(1)] {
            if let Some(reference) = self.sema.reference_at(main, offset) {
                let resolved = match reference.target {
                    Target::Definition(id) => Resolved::Definition(id),
                    Target::Builtin | Target::CommandLine => Resolved::Other,
                };
                return Some((reference.span, resolved));
            }
            if let Some((id, definition)) = self.sema.definition_at(main, offset) {
                return Some((definition.name_span, Resolved::Definition(id)));
            }
        }
        None
    }

    /// Where the name (or the `include`/`use` path) at `position` is defined.
    pub fn goto_definition(&self, position: LineCol) -> Option<FileRange> {
        let offset = self.offset(position);
        let main = self.sema.main;
        if let Some(link) = self
            .sema
            .links
            .iter()
            .find(|l| l.file == main && l.span.contains(offset))
        {
            return Some(self.file_range(link.target?, Span::empty(0)));
        }
        let (_, Resolved::Definition(id)) = self.resolve_at(offset)? else {
            return None;
        };
        let definition = self.sema.definition(id)?;
        Some(self.file_range(definition.file, definition.name_span))
    }

    /// The definitions that are one variable: an assignment and its reassignments in one scope
    /// (linked by `redefines`, each to the one before), found in one pass over the definitions.
    fn same_variable(&self, id: DefId) -> HashSet<DefId> {
        let mut linked: HashMap<DefId, Vec<DefId>> = HashMap::new();
        for (i, definition) in self.sema.definitions.iter().enumerate() {
            if let Some(earlier) = definition.redefines {
                let later = DefId(i as u32);
                linked.entry(later).or_default().push(earlier);
                linked.entry(earlier).or_default().push(later);
            }
        }
        let mut ids = HashSet::from([id]);
        let mut pending = vec![id];
        while let Some(next) = pending.pop() {
            for &other in linked.get(&next).into_iter().flatten() {
                if ids.insert(other) {
                    pending.push(other);
                }
            }
        }
        ids
    }

    /// Every occurrence of the name at `position`: its uses, and its definitions when
    /// `include_declaration` is set. Sorted by file and position.
    pub fn references(&self, position: LineCol, include_declaration: bool) -> Vec<FileRange> {
        let Some((_, Resolved::Definition(id))) = self.resolve_at(self.offset(position)) else {
            return Vec::new();
        };
        let ids = self.same_variable(id);
        let mut spans = Vec::new();
        if include_declaration {
            spans.extend(
                ids.iter()
                    .filter_map(|&id| self.sema.definition(id))
                    .map(|definition| (definition.file, definition.name_span)),
            );
        }
        spans.extend(
            self.sema
                .references
                .iter()
                .filter(|r| matches!(r.target, Target::Definition(d) if ids.contains(&d)))
                .map(|r| (r.file, r.span)),
        );
        spans.sort();
        spans.dedup();
        spans
            .into_iter()
            .map(|(file, span)| self.file_range(file, span))
            .collect()
    }

    /// Checks that the name at `position` can be renamed.
    pub fn prepare_rename(&self, position: LineCol) -> Result<RenameTarget, RenameError> {
        let (span, resolved) = self
            .resolve_at(self.offset(position))
            .ok_or(RenameError::NoName)?;
        let name = self.text().get(span.range()).unwrap_or_default().to_owned();
        match resolved {
            Resolved::Definition(_) => Ok(RenameTarget {
                range: self.range(self.sema.main, span),
                name,
            }),
            Resolved::Other => Err(RenameError::Builtin(name)),
        }
    }

    /// The edits renaming the name at `position` to `new_name`: every occurrence, in every file.
    pub fn rename(&self, position: LineCol, new_name: &str) -> Result<Vec<FileRange>, RenameError> {
        let target = self.prepare_rename(position)?;
        let special = target.name.starts_with('$');
        let body = if special {
            new_name.strip_prefix('$')
        } else {
            Some(new_name)
        };
        let valid = body.is_some_and(|body| {
            let mut chars = body.chars();
            chars.next().is_some_and(|c| {
                c == '_' || c.is_ascii_alphabetic() || (special && c.is_ascii_digit())
            }) && chars.all(|c| c == '_' || c.is_ascii_alphanumeric())
        }) && !KEYWORDS.contains(&new_name);
        if !valid {
            return Err(RenameError::InvalidName(new_name.to_owned()));
        }
        Ok(self.references(position, true))
    }
}
