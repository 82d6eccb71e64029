//! The stability suite: stiff and extreme scenes, each run through check → evaluate → DNF →
//! sample → CPU render, with its measured errors and the checks that failed.
//!
//! Every case file starts with header comments:
//!
//! ```text
//! // stresses: what is hard about it (may continue on more comment lines)
//! // expect: ok | empty | error E0600 | known-failure CHECK…
//! // radius: 0.05   (optional: the sample radius relative to the diagonal)
//! // outcome: free text on what was measured (optional; any other comment line after
//! // `expect:` is ignored too)
//! ```
//!
//! `ok`: no error and every check passes; `empty`: no error and no surface at all; `error CODE`:
//! the pipeline stops with that diagnostic; `known-failure CHECK…`: exactly the named checks
//! fail (see [`Check`]), so a fix shows up as a test failure until the header is updated.

use std::fmt;
use std::path::Path;
use std::time::Duration;

use qcsg_csg::DnfOptions;
use qcsg_render::ImageSize;

use crate::image::{camera_for, frame_is_finite, ray_traced};
use crate::measure::{Measured, References, measure};
use crate::pipeline::compile_file;
use crate::reference::diagonal;

/// The default sample radius, relative to the scene's diagonal.
pub const DEFAULT_RELATIVE_RADIUS: f64 = 0.05;

/// Random lines cast for surface reference points.
pub const REFERENCE_RAYS: usize = 1500;

/// Random lines cast for feature-curve reference points.
pub const EDGE_RAYS: usize = 300;

/// The fewest surface reference points for a coverage check to mean something.
pub const MIN_REFERENCE_POINTS: usize = 100;

/// The size of the rendered check image.
pub const IMAGE_SIZE: (u32, u32) = (48, 36);

/// What a case expects.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Expect {
    /// No error; every check passes.
    Ok,
    /// No error; nothing to sample or render.
    Empty,
    /// The pipeline stops with this error code.
    Error(String),
    /// Exactly these checks fail.
    KnownFailure(Vec<Check>),
}

/// One check of a case's output.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Check {
    /// A quadric of the DNF, a sample or a pixel's depth is NaN or infinite.
    NonFinite,
    /// No samples (for a case that is not empty).
    NoSamples,
    /// A sample is farther from its quadric than [`crate::measure::on_surface_limit`] allows.
    OnSurface,
    /// A sample is not on the CSG surface.
    OffSurface,
    /// A reference point has no sample on its quadric within the radius.
    Coverage,
    /// The sampler gave up a rectangle it could not prove covered.
    Unresolved,
    /// Fewer than [`MIN_REFERENCE_POINTS`] reference points were found.
    References,
    /// The rendered image is empty although the solid's box is thick enough on every axis to
    /// cover a pixel of it (see [`run_case`]).
    Render,
}

impl Check {
    /// Every check, in report order.
    pub const ALL: [Check; 8] = [
        Check::NonFinite,
        Check::NoSamples,
        Check::OnSurface,
        Check::OffSurface,
        Check::Coverage,
        Check::Unresolved,
        Check::References,
        Check::Render,
    ];

    /// Its name in headers and reports.
    pub fn name(self) -> &'static str {
        match self {
            Check::NonFinite => "non-finite",
            Check::NoSamples => "no-samples",
            Check::OnSurface => "on-surface",
            Check::OffSurface => "off-surface",
            Check::Coverage => "coverage",
            Check::Unresolved => "unresolved",
            Check::References => "references",
            Check::Render => "render",
        }
    }

    /// The check with this name.
    pub fn from_name(name: &str) -> Option<Check> {
        Check::ALL.into_iter().find(|c| c.name() == name)
    }
}

impl fmt::Display for Check {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A case file's header.
#[derive(Clone, Debug, PartialEq)]
pub struct Header {
    /// What the case stresses.
    pub stresses: String,
    /// What it expects.
    pub expect: Expect,
    /// The sample radius relative to the diagonal.
    pub relative_radius: f64,
}

/// Reads the header comments of a case; `Err` names what is missing or malformed.
pub fn parse_header(text: &str) -> Result<Header, String> {
    let mut stresses = String::new();
    let mut expect = None;
    let mut relative_radius = DEFAULT_RELATIVE_RADIUS;
    let mut in_stresses = false;
    for line in text.lines() {
        let Some(comment) = line.trim().strip_prefix("//") else {
            break;
        };
        let comment = comment.trim();
        if let Some(rest) = comment.strip_prefix("stresses:") {
            stresses = rest.trim().to_owned();
            in_stresses = true;
        } else if let Some(rest) = comment.strip_prefix("expect:") {
            in_stresses = false;
            let mut words = rest.split_whitespace();
            expect = Some(match words.next() {
                Some("ok") => Expect::Ok,
                Some("empty") => Expect::Empty,
                Some("error") => Expect::Error(
                    words
                        .next()
                        .ok_or("`expect: error` needs a code")?
                        .to_owned(),
                ),
                Some("known-failure") => {
                    let mut checks = words
                        .map(|w| Check::from_name(w).ok_or(format!("unknown check `{w}`")))
                        .collect::<Result<Vec<_>, _>>()?;
                    checks.sort();
                    if checks.is_empty() {
                        return Err("`expect: known-failure` needs check names".into());
                    }
                    Expect::KnownFailure(checks)
                }
                other => return Err(format!("unknown expectation {other:?}")),
            });
        } else if let Some(rest) = comment.strip_prefix("radius:") {
            in_stresses = false;
            relative_radius = rest
                .trim()
                .parse()
                .map_err(|_| format!("bad radius `{}`", rest.trim()))?;
        } else if in_stresses {
            stresses.push(' ');
            stresses.push_str(comment);
        }
    }
    if stresses.is_empty() {
        return Err("no `// stresses:` line".into());
    }
    let expect = expect.ok_or("no `// expect:` line")?;
    Ok(Header {
        stresses,
        expect,
        relative_radius,
    })
}

/// What running a case gave.
#[derive(Clone, Debug)]
pub struct CaseResult {
    /// The case's header.
    pub header: Header,
    /// Error codes of the pipeline, in order.
    pub error_codes: Vec<&'static str>,
    /// Warning codes of the pipeline, in order.
    pub warning_codes: Vec<&'static str>,
    /// DNF size: terms and literals.
    pub terms: usize,
    /// Literals over all terms.
    pub literals: usize,
    /// The scene's diagonal.
    pub diagonal: f64,
    /// The sampling and its errors (absent when the pipeline stopped or the scene is empty).
    pub measured: Option<Measured>,
    /// Reference points on the surface and on feature curves.
    pub reference_counts: (usize, usize),
    /// Pixels of the check image that see the solid.
    pub image_hits: usize,
    /// Time of the CPU render of the check image.
    pub render_time: Duration,
    /// The checks that failed, sorted.
    pub failed: Vec<Check>,
}

impl CaseResult {
    /// Whether the outcome is what the header expects; `Err` says how it differs.
    pub fn verdict(&self) -> Result<(), String> {
        match &self.header.expect {
            Expect::Error(code) => {
                if self.error_codes.iter().any(|c| c == code) {
                    Ok(())
                } else {
                    Err(format!(
                        "expected error {code}, got errors {:?}",
                        self.error_codes
                    ))
                }
            }
            _ if !self.error_codes.is_empty() => {
                Err(format!("unexpected errors {:?}", self.error_codes))
            }
            Expect::Ok if self.failed.is_empty() => Ok(()),
            Expect::Ok => Err(format!("failed checks: {}", names(&self.failed))),
            Expect::Empty => {
                let samples = self
                    .measured
                    .as_ref()
                    .map_or(0, |m| m.sampling.samples.len());
                if samples == 0
                    && self.image_hits == 0
                    && self.reference_counts.0 == 0
                    && !self.failed.contains(&Check::NonFinite)
                {
                    Ok(())
                } else {
                    Err(format!(
                        "expected nothing, got {samples} samples, {} reference points, {} pixels",
                        self.reference_counts.0, self.image_hits
                    ))
                }
            }
            Expect::KnownFailure(checks) if *checks == self.failed => Ok(()),
            Expect::KnownFailure(checks) => Err(format!(
                "known failure of [{}] changed: now failing [{}] (update the header if it was fixed)",
                names(checks),
                names(&self.failed)
            )),
        }
    }
}

/// Check names joined by spaces.
pub fn names(checks: &[Check]) -> String {
    checks
        .iter()
        .map(|c| c.name())
        .collect::<Vec<_>>()
        .join(" ")
}

/// Runs one case file through the whole pipeline and measures it.
pub fn run_case(path: &Path) -> Result<CaseResult, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|err| format!("cannot read `{}`: {err}", path.display()))?;
    let header = parse_header(&text).map_err(|err| format!("{}: {err}", path.display()))?;
    let compiled = compile_file(path, &DnfOptions::default())?;
    let mut result = CaseResult {
        error_codes: compiled.error_codes(),
        warning_codes: compiled.warning_codes(),
        header,
        terms: 0,
        literals: 0,
        diagonal: 0.0,
        measured: None,
        reference_counts: (0, 0),
        image_hits: 0,
        render_time: Duration::ZERO,
        failed: Vec::new(),
    };
    let Some(dnf) = compiled.dnf else {
        return Ok(result);
    };
    let mut failed = Vec::new();
    result.terms = dnf.terms.len();
    result.literals = dnf.literal_count();
    let diag = diagonal(&dnf);
    result.diagonal = diag;
    let finite_dnf = dnf.quadrics.iter().all(|q| {
        q.quadric.origin().is_finite() && q.quadric.coefficients().iter().all(|c| c.is_finite())
    });
    if !finite_dnf {
        failed.push(Check::NonFinite);
    }
    let has_surface = !dnf.terms.is_empty() && diag > 0.0;
    if has_surface {
        let refs = References::find(&dnf, REFERENCE_RAYS, EDGE_RAYS);
        result.reference_counts = (refs.surface.len(), refs.edges.len());
        let radius = result.header.relative_radius * diag;
        match measure(&dnf, radius, &refs) {
            Ok(m) => {
                if m.non_finite > 0 {
                    failed.push(Check::NonFinite);
                }
                if m.sampling.samples.is_empty() {
                    failed.push(Check::NoSamples);
                }
                if m.on_surface > m.on_surface_limit || m.on_surface.is_nan() {
                    failed.push(Check::OnSurface);
                }
                if m.off_csg_surface > 0 {
                    failed.push(Check::OffSurface);
                }
                if m.coverage.beyond_reach > 0 || m.edge_coverage.beyond_reach > 0 {
                    failed.push(Check::Coverage);
                }
                if m.sampling.stats.unresolved() > 0 {
                    failed.push(Check::Unresolved);
                }
                result.measured = Some(m);
            }
            Err(_) => failed.push(Check::NonFinite),
        }
        if refs.surface.len() < MIN_REFERENCE_POINTS {
            failed.push(Check::References);
        }
    }
    let size = ImageSize::new(IMAGE_SIZE.0, IMAGE_SIZE.1).map_err(|err| err.to_string())?;
    if let Some(camera) = camera_for(&dnf, size) {
        let (frame, time) = ray_traced(&dnf, &camera, size);
        result.render_time = time;
        result.image_hits = frame.hit_count();
        if !frame_is_finite(&frame) {
            failed.push(Check::NonFinite);
        }
        // A solid much thinner than a pixel on some axis (a long rod) can fall between pixel
        // centres; only a box whose smallest side reaches a pixel must show up.
        let extent = dnf.bounds.max - dnf.bounds.min;
        let thick = extent.min_element() * f64::from(IMAGE_SIZE.1) >= extent.max_element();
        if has_surface && thick && frame.hit_count() == 0 {
            failed.push(Check::Render);
        }
    }
    failed.sort();
    failed.dedup();
    result.failed = failed;
    Ok(result)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headers_parse_and_reject() {
        let h = parse_header(
            "// stresses: a thin wall\n// down to 1e-6.\n// expect: known-failure unresolved coverage\n// radius: 0.3\n// outcome: notes\ncube(1);",
        )
        .expect("parses");
        assert_eq!(h.stresses, "a thin wall down to 1e-6.");
        assert_eq!(
            h.expect,
            Expect::KnownFailure(vec![Check::Coverage, Check::Unresolved])
        );
        assert_eq!(h.relative_radius, 0.3);
        let h = parse_header("// stresses: x\n// expect: error E0600\n").expect("parses");
        assert_eq!(h.expect, Expect::Error("E0600".into()));
        assert_eq!(h.relative_radius, DEFAULT_RELATIVE_RADIUS);
        for bad in [
            "// expect: ok\n",
            "// stresses: x\n",
            "// stresses: x\n// expect: maybe\n",
            "// stresses: x\n// expect: known-failure\n",
            "// stresses: x\n// expect: known-failure slow\n",
            "// stresses: x\n// expect: ok\n// radius: big\n",
        ] {
            assert!(parse_header(bad).is_err(), "accepted {bad:?}");
        }
    }

    #[test]
    fn a_changed_known_failure_fails_the_verdict() {
        let mut result = CaseResult {
            header: parse_header("// stresses: x\n// expect: known-failure unresolved\n")
                .expect("parses"),
            error_codes: Vec::new(),
            warning_codes: Vec::new(),
            terms: 1,
            literals: 1,
            diagonal: 1.0,
            measured: None,
            reference_counts: (100, 0),
            image_hits: 10,
            render_time: Duration::ZERO,
            failed: vec![Check::Unresolved],
        };
        assert!(result.verdict().is_ok());
        result.failed.clear();
        assert!(result.verdict().is_err(), "a fixed failure must be noticed");
        result.failed = vec![Check::Coverage, Check::Unresolved];
        assert!(result.verdict().is_err(), "a new failure must be noticed");
        result.header.expect = Expect::Ok;
        assert!(result.verdict().is_err());
        result.failed.clear();
        assert!(result.verdict().is_ok());
        result.error_codes = vec!["E0600"];
        assert!(
            result.verdict().is_err(),
            "an unexpected error must be noticed"
        );
    }
}
