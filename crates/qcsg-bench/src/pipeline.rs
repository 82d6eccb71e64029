//! From source text to the DNF of the solid: check, evaluate, normal form, as `qcsg` does it,
//! with every diagnostic kept so that a measurement can tell an expected error from a failure.

use std::path::Path;
use std::time::{Duration, Instant};

use qcsg_csg::{Dnf, DnfOptions, DnfSize, build_dnf, unpruned_size};
use qcsg_diag::{Diagnostic, Severity};
use qcsg_eval::{EvalOptions, evaluate};
use qcsg_sema::{CheckOptions, FsLoader, check_file};

/// A program run through the front end.
#[derive(Debug)]
pub struct Compiled {
    /// The solid, when no stage reported an error.
    pub dnf: Option<Dnf>,
    /// Every diagnostic of every stage, in stage order.
    pub diagnostics: Vec<Diagnostic>,
    /// Time spent checking and evaluating.
    pub front_end: Duration,
    /// Time spent building the DNF.
    pub normal_form: Duration,
    /// The size of the DNF multiplied out with no pruning at all (see [`unpruned_size`]).
    pub unpruned: Option<DnfSize>,
}

impl Compiled {
    /// The codes of the error diagnostics, in order, without repeats.
    pub fn error_codes(&self) -> Vec<&'static str> {
        let mut codes: Vec<&'static str> = Vec::new();
        for d in self.diagnostics.iter().filter(|d| d.is_error()) {
            if !codes.contains(&d.code) {
                codes.push(d.code);
            }
        }
        codes
    }

    /// The codes of the warnings, in order, without repeats.
    pub fn warning_codes(&self) -> Vec<&'static str> {
        let mut codes: Vec<&'static str> = Vec::new();
        for d in &self.diagnostics {
            if d.severity == Severity::Warning && !codes.contains(&d.code) {
                codes.push(d.code);
            }
        }
        codes
    }
}

/// Checks, evaluates and normalises a program given as text (`name` is how diagnostics call
/// it; `include` paths are looked up beside it).
pub fn compile_source(name: &str, text: String, options: &DnfOptions) -> Compiled {
    let start = Instant::now();
    let mut analysis = check_file(name, text, &CheckOptions::default(), &FsLoader);
    let mut diagnostics = std::mem::take(&mut analysis.diagnostics);
    if diagnostics.iter().any(Diagnostic::is_error) {
        return Compiled {
            dnf: None,
            diagnostics,
            front_end: start.elapsed(),
            normal_form: Duration::ZERO,
            unpruned: None,
        };
    }
    let evaluation = evaluate(&analysis, &EvalOptions::default());
    let failed = evaluation.has_errors();
    diagnostics.extend(evaluation.diagnostics);
    let front_end = start.elapsed();
    if failed {
        return Compiled {
            dnf: None,
            diagnostics,
            front_end,
            normal_form: Duration::ZERO,
            unpruned: None,
        };
    }
    let unpruned = evaluation
        .dag
        .root()
        .map(|root| unpruned_size(&evaluation.dag, root));
    let start = Instant::now();
    let (dnf, more) = match build_dnf(&evaluation.dag, options) {
        Ok(mut dnf) => {
            let warnings = std::mem::take(&mut dnf.warnings);
            (Some(dnf), warnings)
        }
        Err(errors) => (None, errors),
    };
    diagnostics.extend(more);
    Compiled {
        dnf,
        diagnostics,
        front_end,
        normal_form: start.elapsed(),
        unpruned,
    }
}

/// [`compile_source`] on a file; an unreadable file is an `Err` with the reason.
pub fn compile_file(path: &Path, options: &DnfOptions) -> Result<Compiled, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|err| format!("cannot read `{}`: {err}", path.display()))?;
    Ok(compile_source(&path.to_string_lossy(), text, options))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn size_of(text: &str) -> DnfSize {
        compile_source("t.qcsg", text.into(), &DnfOptions::default())
            .unpruned
            .expect("a root")
    }

    #[test]
    fn unpruned_sizes_multiply_out() {
        // A cube is the intersection of three slabs: one term of three literals.
        assert_eq!(
            size_of("cube(1);"),
            DnfSize {
                terms: 1.0,
                literals: 3.0
            }
        );
        // Cube minus cube: 3 literals ∩ (¬a ∪ ¬b ∪ ¬c) = 3 terms of 4 literals.
        assert_eq!(
            size_of("difference() { cube(1); translate([0.5, 0, 0]) cube(1); }"),
            DnfSize {
                terms: 3.0,
                literals: 12.0
            }
        );
        // Two balls united: two terms of one literal.
        assert_eq!(
            size_of("sphere(1); translate([3, 0, 0]) sphere(1);"),
            DnfSize {
                terms: 2.0,
                literals: 2.0
            }
        );
    }
}
