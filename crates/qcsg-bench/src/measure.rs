//! One measurement of a scene at one radius: sample it (timed), then measure every error of the
//! samples against reference points found independently of the sampler.

use std::time::{Duration, Instant};

use qcsg_csg::Dnf;
use qcsg_sample::{SampleError, Sampling, sample};

use crate::metrics::{
    Coverage, SampleIndex, coverage, non_finite_samples, on_surface_error, samples_off_csg_surface,
};
use crate::reference::{SurfacePoint, diagonal, edge_points, quadric_points, reference_points};

/// Slack allowed beyond the radius for rounding, relative to the diagonal (reference points
/// and samples are both only accurate to rounding).
pub const COVERAGE_SLACK: f64 = 4e-9;

/// The largest on-surface error the guarantee allows, relative to the diagonal, near the
/// origin (see [`on_surface_limit`] far from it).
pub const ON_SURFACE_LIMIT: f64 = 1e-9;

/// The largest on-surface error allowed for a scene, relative to its diagonal:
/// [`ON_SURFACE_LIMIT`], plus eight units in the last place of the largest coordinate of the
/// scene's box, since no f64 position can be closer to a surface than rounding of its own
/// coordinates allows (a part of size 1 at 1e9 has coordinates rounded to 1.2e-7).
pub fn on_surface_limit(dnf: &Dnf) -> f64 {
    let diag = diagonal(dnf);
    let magnitude = dnf.bounds.min.abs().max(dnf.bounds.max.abs()).max_element();
    if diag > 0.0 && magnitude.is_finite() {
        ON_SURFACE_LIMIT + 8.0 * f64::EPSILON * magnitude / diag
    } else {
        ON_SURFACE_LIMIT
    }
}

/// Lines cast through each quadric's origin for reference points ([`quadric_points`]).
pub const QUADRIC_LINES: usize = 48;

/// Reference points of a scene: on its surfaces and on its feature curves.
#[derive(Clone, Debug, Default)]
pub struct References {
    /// Points on the CSG surface from random lines.
    pub surface: Vec<SurfacePoint>,
    /// Points on the feature curves.
    pub edges: Vec<SurfacePoint>,
}

impl References {
    /// Reference points from `rays` random lines and [`QUADRIC_LINES`] lines through each
    /// quadric's origin, and feature-curve points from `edge_rays`.
    pub fn find(dnf: &Dnf, rays: usize, edge_rays: usize) -> Self {
        let mut surface = reference_points(dnf, rays, 99);
        surface.extend(quadric_points(dnf, QUADRIC_LINES, 5));
        Self {
            surface,
            edges: if edge_rays == 0 {
                Vec::new()
            } else {
                edge_points(dnf, edge_rays, 7)
            },
        }
    }
}

/// A timed sampling and its measured errors.
#[derive(Clone, Debug)]
pub struct Measured {
    /// The radius, in world units.
    pub radius: f64,
    /// The samples and the sampler's counters.
    pub sampling: Sampling,
    /// Wall time of the sampler.
    pub time: Duration,
    /// Largest on-surface error of a sample, relative to the diagonal.
    pub on_surface: f64,
    /// The largest on-surface error allowed ([`on_surface_limit`]).
    pub on_surface_limit: f64,
    /// Samples that an independent test finds off the CSG surface.
    pub off_csg_surface: usize,
    /// Samples with a NaN or infinite field.
    pub non_finite: usize,
    /// Coverage of the surface reference points.
    pub coverage: Coverage,
    /// Coverage of the feature-curve reference points.
    pub edge_coverage: Coverage,
}

impl Measured {
    /// The reach allowed by the guarantee: the radius plus rounding slack.
    pub fn reach(&self, diag: f64) -> f64 {
        self.radius * (1.0 + 1e-9) + COVERAGE_SLACK * diag
    }

    /// The worst coverage distance over both kinds of reference points, in units of the radius.
    pub fn coverage_over_radius(&self) -> f64 {
        self.coverage
            .max_distance
            .max(self.edge_coverage.max_distance)
            / self.radius
    }

    /// Whether every guarantee holds: samples finite, on their quadric and on the CSG surface,
    /// and every reference point within reach of a sample on its quadric.
    pub fn guarantee_holds(&self, diag: f64) -> bool {
        self.non_finite == 0
            && self.on_surface <= self.on_surface_limit
            && self.off_csg_surface == 0
            && self.coverage.beyond_reach == 0
            && self.edge_coverage.beyond_reach == 0
            && self.sampling.stats.unresolved() == 0
            && self.reach(diag).is_finite()
    }
}

/// Samples `dnf` at `radius` and measures the errors against `refs`.
pub fn measure(dnf: &Dnf, radius: f64, refs: &References) -> Result<Measured, SampleError> {
    let start = Instant::now();
    let sampling = sample(dnf, radius)?;
    let time = start.elapsed();
    let diag = diagonal(dnf);
    let samples = &sampling.samples;
    let index = SampleIndex::new(samples, dnf.quadrics.len());
    let reach = radius * (1.0 + 1e-9) + COVERAGE_SLACK * diag;
    // Quadrics this close to a reference point pass through it (coincident faces).
    let tolerance = on_surface_limit(dnf) * diag;
    Ok(Measured {
        radius,
        time,
        on_surface: on_surface_error(dnf, samples),
        on_surface_limit: on_surface_limit(dnf),
        off_csg_surface: samples_off_csg_surface(dnf, samples, 1e-9 * diag),
        non_finite: non_finite_samples(samples),
        coverage: coverage(dnf, &index, &refs.surface, reach, tolerance),
        edge_coverage: coverage(dnf, &index, &refs.edges, reach, tolerance),
        sampling,
    })
}
