//! Which diagnostics of a run are printed for people, when there are too many to read.
//!
//! A file that is broken everywhere (a binary file, a paste gone wrong) can have tens of thousands
//! of diagnostics; nobody reads past the first screens, and printing them all takes longer than
//! the check. So at most [`MAX_SHOWN`] errors, warnings and hints are printed, at most
//! [`MAX_SHOWN_PER_FILE`] of any one file, so that one broken file does not hide the others.
//! Errors come first: the ones printed are the first errors, then, while room is left, the first
//! warnings and then hints; they are printed in their usual order. `echo` output (infos) is the
//! program's output and is always printed (the evaluator bounds it). One line says how many were
//! left out and that `--format json` lists every one.

use std::collections::HashMap;

use qcsg_diag::{Diagnostic, Severity, SourceMap};

/// Most errors, warnings and hints printed by one run.
pub const MAX_SHOWN: usize = 100;
/// Most errors, warnings and hints printed from one source file.
pub const MAX_SHOWN_PER_FILE: usize = 50;

/// The diagnostics to print, and what was left out.
#[derive(Debug, PartialEq, Eq)]
pub struct Selection {
    /// For each diagnostic, in order, whether it is printed.
    pub shown: Vec<bool>,
    /// How many were left out, by [`Severity`] (error, warning, info, hint).
    pub omitted: [usize; 4],
}

/// Chooses among `diagnostics` (each with the source map its file is in) which to print.
pub fn select(diagnostics: &[(&SourceMap, &Diagnostic)]) -> Selection {
    let mut shown: Vec<bool> = diagnostics
        .iter()
        .map(|(_, d)| d.severity == Severity::Info)
        .collect();
    let mut total = 0;
    let mut per_file: HashMap<(*const SourceMap, u32), usize> = HashMap::new();
    for severity in [Severity::Error, Severity::Warning, Severity::Hint] {
        for (i, (sources, diagnostic)) in diagnostics.iter().enumerate() {
            if diagnostic.severity != severity || total == MAX_SHOWN {
                continue;
            }
            let in_file = per_file
                .entry((std::ptr::from_ref(*sources), diagnostic.file.0))
                .or_default();
            if *in_file < MAX_SHOWN_PER_FILE {
                *in_file += 1;
                total += 1;
                shown[i] = true;
            }
        }
    }
    let mut omitted = [0; 4];
    for ((_, diagnostic), &shown) in diagnostics.iter().zip(&shown) {
        if !shown {
            omitted[diagnostic.severity as usize] += 1;
        }
    }
    Selection { shown, omitted }
}

/// `"… 7950 more errors and 24 more warnings not shown (--format json lists them all)"`, or
/// nothing when none was left out.
pub fn omitted_line(omitted: [usize; 4]) -> Option<String> {
    let words = [
        ("error", "errors"),
        ("warning", "warnings"),
        ("info", "infos"),
        ("hint", "hints"),
    ];
    let parts: Vec<String> = omitted
        .iter()
        .zip(words)
        .filter(|(n, _)| **n > 0)
        .map(|(&n, (one, many))| format!("{n} more {}", if n == 1 { one } else { many }))
        .collect();
    let list = match parts.as_slice() {
        [] => return None,
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    };
    Some(format!("… {list} not shown (--format json lists them all)"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use qcsg_diag::{FileId, Span};

    fn diagnostic(severity: Severity, file: u32, at: usize) -> Diagnostic {
        Diagnostic::new(severity, "E0000", "x", FileId(file), Span::empty(at))
    }

    #[test]
    fn errors_first_then_warnings_within_both_limits() {
        let sources = SourceMap::new();
        let other = SourceMap::new();
        let mut all = Vec::new();
        // A file whose warnings come before its errors, and more errors than a file may show.
        for at in 0..40 {
            all.push((&sources, diagnostic(Severity::Warning, 0, at)));
        }
        for at in 40..100 {
            all.push((&sources, diagnostic(Severity::Error, 0, at)));
        }
        all.push((&sources, diagnostic(Severity::Info, 0, 100)));
        // A second file of the same run, and a file of another run (another source map).
        for at in 0..30 {
            all.push((&sources, diagnostic(Severity::Hint, 1, at)));
        }
        for at in 0..80 {
            all.push((&other, diagnostic(Severity::Error, 0, at)));
        }
        let refs: Vec<(&SourceMap, &Diagnostic)> = all.iter().map(|(s, d)| (*s, d)).collect();
        let selection = select(&refs);
        let shown =
            |range: std::ops::Range<usize>| selection.shown[range].iter().filter(|&&s| s).count();
        // The first 50 errors of file 0; no room for its warnings; the echo is always shown.
        assert_eq!(shown(0..40), 0);
        assert_eq!(shown(40..100), 50);
        assert!(selection.shown[40] && !selection.shown[99]);
        assert_eq!(shown(100..101), 1);
        // The other run's file has 50 errors shown, which leaves no room for the hints.
        assert_eq!(shown(131..211), 50);
        assert_eq!(shown(101..131), 0);
        assert_eq!(selection.omitted, [10 + 30, 40, 0, 30]);
        assert_eq!(
            omitted_line(selection.omitted).as_deref(),
            Some(
                "… 40 more errors, 40 more warnings and 30 more hints not shown (--format json \
                 lists them all)"
            )
        );
        assert_eq!(
            omitted_line([0, 1, 0, 0]).as_deref(),
            Some("… 1 more warning not shown (--format json lists them all)")
        );
        assert_eq!(omitted_line([0; 4]), None);
    }
}
