//! Errors of a sampling, measured against the exact surface: coverage error (how far the
//! farthest reference point is from its nearest sample on the same quadric, or on a quadric
//! coincident with it there), on-surface error
//! (first-order distance of each sample to its quadric), samples off the CSG surface, and
//! non-finite output.

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use qcsg_csg::Dnf;
use qcsg_quadric::{DVec3, Quadric};
use qcsg_sample::Samples;

use crate::reference::{SurfacePoint, diagonal};

/// `|Q(p)| / ‖∇Q(p)‖`: the first-order distance of `p` to the quadric's surface (0 at a
/// singular point that lies on it, infinite at one that does not).
pub fn surface_residual(q: &Quadric, p: DVec3) -> f64 {
    let g = q.gradient(p).length();
    if g == 0.0 {
        return if q.value(p) == 0.0 {
            0.0
        } else {
            f64::INFINITY
        };
    }
    q.value(p).abs() / g
}

/// The signed first-order distance `Q(p) / ‖∇Q(p)‖` (negative inside).
pub fn signed_residual(q: &Quadric, p: DVec3) -> f64 {
    let g = q.gradient(p).length();
    if g == 0.0 {
        return q.value(p);
    }
    q.value(p) / g
}

/// The largest on-surface error of the samples, relative to the scene's diagonal (0 for no
/// samples; NaN never: a non-finite residual counts as infinite).
pub fn on_surface_error(dnf: &Dnf, samples: &Samples) -> f64 {
    let diag = diagonal(dnf);
    samples
        .iter()
        .map(|s| {
            let residual = dnf
                .quadrics
                .get(s.quadric as usize)
                .map_or(f64::INFINITY, |q| surface_residual(&q.quadric, s.position));
            let relative = residual / diag;
            if relative.is_nan() {
                f64::INFINITY
            } else {
                relative
            }
        })
        .fold(0.0, f64::max)
}

/// How many samples are not on the CSG surface by an independent test with tolerance `tol`:
/// outside their term's box or one of its other literals, or strictly inside another term.
pub fn samples_off_csg_surface(dnf: &Dnf, samples: &Samples, tol: f64) -> usize {
    samples
        .iter()
        .filter(|s| {
            let Some(term) = dnf.terms.get(s.term as usize) else {
                return true;
            };
            let p = s.position;
            let b = term.bounds;
            let outside_box = (b.min - p).max(p - b.max).max_element() > tol;
            let outside_own = term.literals.iter().any(|&j| {
                j != s.quadric && signed_residual(&dnf.quadrics[j as usize].quadric, p) > tol
            });
            let inside_other = dnf.terms.iter().enumerate().any(|(i, other)| {
                i != s.term as usize
                    && other
                        .literals
                        .iter()
                        .all(|&j| signed_residual(&dnf.quadrics[j as usize].quadric, p) < -tol)
                    && (p - other.bounds.min)
                        .min(other.bounds.max - p)
                        .min_element()
                        > tol
            });
            outside_box || outside_own || inside_other
        })
        .count()
}

/// How many samples carry a NaN or infinite position, normal or radius.
pub fn non_finite_samples(samples: &Samples) -> usize {
    samples
        .iter()
        .filter(|s| !(s.position.is_finite() && s.normal.is_finite() && s.radius.is_finite()))
        .count()
}

/// The samples of each quadric in a k-d tree, for nearest-sample queries.
pub struct SampleIndex {
    trees: Vec<Option<ImmutableKdTree<f64, 3>>>,
}

impl SampleIndex {
    /// Indexes `samples` by quadric (`quadric_count` quadrics; samples of other indices are
    /// ignored).
    pub fn new(samples: &Samples, quadric_count: usize) -> Self {
        let mut points: Vec<Vec<[f64; 3]>> = vec![Vec::new(); quadric_count];
        for s in samples {
            if let Some(list) = points.get_mut(s.quadric as usize)
                && s.position.is_finite()
            {
                list.push(s.position.to_array());
            }
        }
        let trees = points
            .iter()
            .map(|list| {
                if list.is_empty() {
                    None
                } else {
                    ImmutableKdTree::new_from_slice(list).ok()
                }
            })
            .collect();
        Self { trees }
    }

    /// The distance from `p` to the nearest sample on quadric `quadric` (infinite if it has
    /// none).
    pub fn nearest(&self, quadric: u32, p: DVec3) -> f64 {
        match self.trees.get(quadric as usize) {
            Some(Some(tree)) => tree
                .query(&p.to_array())
                .nearest_one::<SquaredEuclidean<f64>>()
                .execute()
                .distance
                .sqrt(),
            _ => f64::INFINITY,
        }
    }
}

/// Coverage of reference points by samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coverage {
    /// Reference points measured.
    pub points: usize,
    /// The largest distance from a reference point to its nearest sample on the same quadric
    /// (infinite when a reference point's quadric has no sample; 0 without reference points).
    pub max_distance: f64,
    /// The reference point where it was found.
    pub worst: Option<SurfacePoint>,
    /// Reference points farther than the allowed reach from every sample of their quadric.
    pub beyond_reach: usize,
}

/// Measures the coverage of `refs` by the samples in `index`; `reach` is the distance allowed
/// (the radius plus rounding slack) for [`Coverage::beyond_reach`].
///
/// A reference point is measured against the samples of its own quadric; where that is beyond
/// reach, also against those of every other quadric whose surface passes within `tolerance` of
/// it. Coincident faces (the top of a block and a pocket's plane cut flush with it) are one
/// piece of surface on two quadrics, and the sampler rightly samples it once, on either.
pub fn coverage(
    dnf: &Dnf,
    index: &SampleIndex,
    refs: &[SurfacePoint],
    reach: f64,
    tolerance: f64,
) -> Coverage {
    let mut result = Coverage {
        points: refs.len(),
        max_distance: 0.0,
        worst: None,
        beyond_reach: 0,
    };
    for point in refs {
        let mut d = index.nearest(point.quadric, point.position);
        if d > reach || d.is_nan() {
            for (j, entry) in dnf.quadrics.iter().enumerate() {
                if j as u32 != point.quadric
                    && surface_residual(&entry.quadric, point.position) <= tolerance
                {
                    d = d.min(index.nearest(j as u32, point.position));
                }
            }
        }
        if d > reach || d.is_nan() {
            result.beyond_reach += 1;
        }
        if d > result.max_distance || d.is_nan() {
            result.max_distance = if d.is_nan() { f64::INFINITY } else { d };
            result.worst = Some(*point);
        }
    }
    result
}
