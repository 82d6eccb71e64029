//! Sets of parameter intervals along a ray, each end labelled with what bounds it there, and
//! the inside-set of one quadric literal along a line.
//!
//! A literal `q ≤ 0` restricted to a line is a quadratic in `t`, so its inside-set is a union
//! of at most two intervals (three pieces of the line, alternating). Its ends are the roots of
//! [`Quadric::intersect_line`]; which pieces are inside is decided by the sign of `q` at a point
//! of each gap, which also carries an unbounded quadric's state at the ray's start. Tangent
//! double roots and lines lying in the surface make no boundary, and zero-length pieces are
//! dropped: the solids are regularised.
//!
//! Literals of a DNF are read through the surfaces they lie on ([`qcsg_csg::coincident`]): the
//! roots are those of each sheet's surface, and the sign in a gap is the surface's, oriented as
//! the literal's sheet (a slab inside both its planes, its complement outside either). Literals
//! that share a surface then cross it at the very same parameter, bit for bit, so that where one
//! leaves and another enters their intervals meet exactly (and merge) and where they face each
//! other across it their intersection is empty: a flush cutter's face is decided by whether the
//! solid changes across it, never by which rounding came out larger.

use qcsg_csg::{Sheet, Surfaces};
use qcsg_quadric::{LineIntersection, Quadric};

use crate::eye::EyeValues;
use crate::raytrace::Ray;

/// What bounds an interval at one of its ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Boundary {
    /// The surface of the DNF quadric with this index.
    Quadric(u32),
    /// The clipping range (a term's box, or the ray's start): not a surface of the solid.
    Clip,
}

impl Boundary {
    /// The order of labels where two bounds meet: the clipping range, then the quadrics by
    /// index (a term's literals ascend, so the first of its literals to reach a bound keeps it,
    /// as when they are intersected in order; a clipping bound and a root never meet, roots
    /// being strictly inside the range).
    fn rank(self) -> u64 {
        match self {
            Self::Clip => 0,
            Self::Quadric(id) => u64::from(id) + 1,
        }
    }
}

/// An interval `[start, end]` of ray parameters, `start < end`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    /// Where it begins.
    pub start: f64,
    /// What bounds it there.
    pub start_by: Boundary,
    /// Where it ends.
    pub end: f64,
    /// What bounds it there.
    pub end_by: Boundary,
}

impl Interval {
    /// The interval `[start, end]` bounded by the clipping range at both ends.
    pub fn clip(start: f64, end: f64) -> Self {
        Self {
            start,
            start_by: Boundary::Clip,
            end,
            end_by: Boundary::Clip,
        }
    }
}

/// Writes into `out` the pieces of `[range.start, range.end]` where `quadric ≤ 0` along `ray`,
/// ascending, bounded by `Boundary::Quadric(id)` at its roots.
pub fn literal_intervals(
    quadric: &Quadric,
    id: u32,
    ray: &Ray,
    range: Interval,
    out: &mut Vec<Interval>,
) {
    let mut roots = [0.0; 4];
    let count = Literal::Own(quadric).roots(id, ray, None, &mut roots);
    Literal::Own(quadric).intervals(id, ray, range, &roots[..count], out);
}

/// [`literal_intervals`] for the DNF quadric `id` (whose quadric is `quadric`), read through the
/// surfaces its sheets lie on (see the module docs). A quadric that `surfaces` does not
/// describe, or without a surface, is read by itself. `eye`: the values of the DNF's quadrics
/// and surfaces at the ray's start, when they were computed for it (the same results, sooner).
/// `roots`: the crossings found along this ray so far, by DNF quadric id (a literal read in
/// several terms is crossed once per ray: its roots do not depend on the term's range).
#[allow(clippy::too_many_arguments)]
pub fn surface_literal_intervals(
    surfaces: &Surfaces,
    quadric: &Quadric,
    id: u32,
    ray: &Ray,
    range: Interval,
    eye: Option<&EyeValues>,
    roots: &mut RayRoots,
    out: &mut Vec<Interval>,
) {
    let literal = Literal::of(surfaces, quadric, id);
    let found = roots.of(id, |found| literal.roots(id, ray, eye, found));
    literal.intervals(id, ray, range, found, out);
}

/// The crossings of the literals' surfaces along one ray, by DNF quadric id, found when first
/// asked for. [`RayRoots::next_ray`] forgets them all at once (a counter, not a clearing).
#[derive(Clone, Debug, Default)]
pub struct RayRoots {
    ray: u32,
    /// Per id: the ray they were found for, how many, the roots ascending.
    found: Vec<(u32, u8, [f64; 4])>,
}

impl RayRoots {
    /// Forgets the roots of the previous ray (of any DNF).
    pub fn next_ray(&mut self) {
        self.ray = self.ray.wrapping_add(1);
        if self.ray == 0 {
            // Once in 2^32 rays: entries of ray 0 could be taken for this ray's.
            self.found.iter_mut().for_each(|entry| entry.0 = u32::MAX);
            self.ray = 1;
        }
    }

    /// The roots of `id` along the current ray, found by `find` (which writes them and returns
    /// how many) unless they are known.
    fn of(&mut self, id: u32, find: impl FnOnce(&mut [f64; 4]) -> usize) -> &[f64] {
        let k = id as usize;
        if k >= self.found.len() {
            self.found.resize(k + 1, (u32::MAX, 0, [0.0; 4]));
        }
        let entry = &mut self.found[k];
        if entry.0 != self.ray {
            let count = find(&mut entry.2);
            *entry = (self.ray, count as u8, entry.2);
        }
        &entry.2[..usize::from(entry.1)]
    }
}

/// How a literal's roots and sign are read.
#[derive(Clone, Copy)]
enum Literal<'a> {
    /// From its own quadric.
    Own(&'a Quadric),
    /// From the surfaces of its sheets (each with a surface in `surfaces`).
    Sheets {
        sheets: &'a [Sheet],
        surfaces: &'a Surfaces,
    },
}

impl<'a> Literal<'a> {
    /// A literal whose sheets share a surface with another is read through its surfaces; one
    /// that shares none by itself, which is the same up to rounding that nothing else sees (and
    /// costs one quadric instead of a slab's two planes).
    fn of(surfaces: &'a Surfaces, quadric: &'a Quadric, id: u32) -> Self {
        let shared = |s: &Sheet| {
            surfaces
                .surface(s.surface)
                .map(|surface| surface.sheets > 1)
        };
        match surfaces.of(id) {
            Some(sheets)
                if sheets.iter().any(|s| shared(s) == Some(true))
                    && sheets.iter().all(|s| shared(s).is_some()) =>
            {
                Self::Sheets { sheets, surfaces }
            }
            _ => Self::Own(quadric),
        }
    }

    /// The crossings of the literal's surface along `ray`, ascending, into `roots`; returns how
    /// many. A double root touches without crossing; a line in the surface crosses nothing.
    fn roots(&self, id: u32, ray: &Ray, eye: Option<&EyeValues>, roots: &mut [f64; 4]) -> usize {
        let mut count = 0;
        let mut add = |q: &Quadric, value: Option<(f64, f64)>| match value.map_or_else(
            || q.intersect_line(ray.origin, ray.direction),
            |value| q.intersect_line_with_value(ray.origin, ray.direction, value),
        ) {
            LineIntersection::One(t) => {
                roots[count] = t;
                count += 1;
            }
            LineIntersection::Two(t0, t1) => {
                roots[count] = t0;
                roots[count + 1] = t1;
                count += 2;
            }
            LineIntersection::Tangent(_) | LineIntersection::None | LineIntersection::Contained => {
            }
        };
        match *self {
            Self::Own(q) => add(q, eye.and_then(|e| e.quadric(id))),
            Self::Sheets { sheets, surfaces } => {
                // At most two sheets (a slab's planes), each a plane: two roots; or one curved.
                for sheet in sheets.iter().take(2) {
                    if let Some(surface) = surfaces.surface(sheet.surface) {
                        add(&surface.quadric, eye.and_then(|e| e.surface(sheet.surface)));
                    }
                }
            }
        }
        roots[..count].sort_unstable_by(f64::total_cmp);
        count
    }

    /// Whether the point at `t` lies strictly inside the literal's solid.
    fn strictly_inside(&self, ray: &Ray, t: f64) -> bool {
        let p = ray.at(t);
        match *self {
            Self::Own(q) => q.value(p) < 0.0,
            Self::Sheets { sheets, surfaces } => {
                let inside = |s: &Sheet| {
                    surfaces.surface(s.surface).is_some_and(|surface| {
                        f64::from(s.orientation) * surface.quadric.value(p) < 0.0
                    })
                };
                // A slab's complement holds both sides: outside either of its planes.
                if sheets.iter().all(|s| s.one_sided) {
                    sheets.iter().all(inside)
                } else {
                    sheets.iter().any(inside)
                }
            }
        }
    }

    /// The pieces of `range` inside the literal, given its `roots` along `ray` (ascending).
    fn intervals(
        &self,
        id: u32,
        ray: &Ray,
        range: Interval,
        roots: &[f64],
        out: &mut Vec<Interval>,
    ) {
        out.clear();
        let mut cuts = [0.0; 4];
        let mut cut_count = 0;
        for &t in roots {
            if t > range.start && t < range.end && (cut_count == 0 || cuts[cut_count - 1] < t) {
                cuts[cut_count] = t;
                cut_count += 1;
            }
        }
        let mut start = range.start;
        let mut start_by = range.start_by;
        let mut open: Option<(f64, Boundary)> = None;
        let ends = cuts[..cut_count]
            .iter()
            .map(|&t| (t, Boundary::Quadric(id)))
            .chain(std::iter::once((range.end, range.end_by)));
        for (end, end_by) in ends {
            // Two samples: one of them may fall on a tangent point, where q = 0 outside the solid.
            let inside = self.strictly_inside(ray, sample_point(start, end, 1.0 / 3.0))
                && self.strictly_inside(ray, sample_point(start, end, 2.0 / 3.0));
            match (inside, open) {
                (true, None) => open = Some((start, start_by)),
                (false, Some((s, s_by))) => {
                    push_nonempty(out, s, s_by, start, start_by);
                    open = None;
                }
                _ => {}
            }
            start = end;
            start_by = end_by;
        }
        if let Some((s, s_by)) = open {
            push_nonempty(out, s, s_by, range.end, range.end_by);
        }
    }
}

/// A parameter strictly inside the gap `(start, end)`, the fraction `f` of the way along it
/// (a distance that grows with `f` when one end is infinite).
fn sample_point(start: f64, end: f64, f: f64) -> f64 {
    match (start.is_finite(), end.is_finite()) {
        (true, true) => (1.0 - f) * start + f * end,
        (true, false) => start + f * (1.0 + start.abs()),
        (false, true) => end - f * (1.0 + end.abs()),
        (false, false) => f,
    }
}

fn push_nonempty(
    out: &mut Vec<Interval>,
    start: f64,
    start_by: Boundary,
    end: f64,
    end_by: Boundary,
) {
    if start < end {
        out.push(Interval {
            start,
            start_by,
            end,
            end_by,
        });
    }
}

/// Writes into `out` the intersection of two ascending sets of disjoint intervals; each result
/// end is labelled by the operand that bounds it (the later start, the earlier end), and where
/// both do, by the label that comes first ([`Boundary::rank`]). So a term's intervals are the
/// same, labels included, in whatever order its literals are intersected.
pub fn intersect_into(a: &[Interval], b: &[Interval], out: &mut Vec<Interval>) {
    out.clear();
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        let (x, y) = (a[i], b[j]);
        let x_starts =
            x.start > y.start || (x.start == y.start && x.start_by.rank() <= y.start_by.rank());
        let (start, start_by) = if x_starts {
            (x.start, x.start_by)
        } else {
            (y.start, y.start_by)
        };
        let x_ends = x.end < y.end || (x.end == y.end && x.end_by.rank() <= y.end_by.rank());
        let (end, end_by) = if x_ends {
            (x.end, x.end_by)
        } else {
            (y.end, y.end_by)
        };
        push_nonempty(out, start, start_by, end, end_by);
        if x.end <= y.end {
            i += 1;
        } else {
            j += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use qcsg_quadric::DVec3;

    fn ray_x() -> Ray {
        Ray {
            origin: DVec3::new(-10.0, 0.0, 0.0),
            direction: DVec3::X,
        }
    }

    #[test]
    fn a_sphere_is_one_interval_bounded_by_it() {
        let sphere = Quadric::sphere(DVec3::ZERO, 2.0).unwrap();
        let mut out = Vec::new();
        literal_intervals(
            &sphere,
            7,
            &ray_x(),
            Interval::clip(0.0, f64::INFINITY),
            &mut out,
        );
        assert_eq!(out.len(), 1);
        assert!((out[0].start - 8.0).abs() < 1e-12 && (out[0].end - 12.0).abs() < 1e-12);
        assert_eq!(out[0].start_by, Boundary::Quadric(7));
        // Its complement: two pieces, the second unbounded.
        literal_intervals(
            &sphere.negated(),
            7,
            &ray_x(),
            Interval::clip(0.0, f64::INFINITY),
            &mut out,
        );
        assert_eq!(out.len(), 2);
        assert_eq!(out[0].start_by, Boundary::Clip);
        assert!(out[1].end.is_infinite());
    }

    #[test]
    fn a_half_space_keeps_its_state_at_the_ray_start() {
        // x ≤ 0: the ray starts inside and leaves at t = 10.
        let half = Quadric::half_space(DVec3::ZERO, DVec3::X).unwrap();
        let mut out = Vec::new();
        literal_intervals(&half, 0, &ray_x(), Interval::clip(0.0, 100.0), &mut out);
        assert_eq!(out.len(), 1);
        assert_eq!((out[0].start, out[0].start_by), (0.0, Boundary::Clip));
        assert!((out[0].end - 10.0).abs() < 1e-12);
        // Parallel to a plane and outside it: nothing.
        let below = Quadric::half_space(DVec3::new(0.0, -1.0, 0.0), DVec3::Y).unwrap();
        literal_intervals(&below, 0, &ray_x(), Interval::clip(0.0, 100.0), &mut out);
        assert!(out.is_empty());
    }

    #[test]
    fn tangent_rays_make_no_interval() {
        let sphere = Quadric::sphere(DVec3::new(0.0, 1.0, 0.0), 1.0).unwrap();
        let mut out = Vec::new();
        literal_intervals(
            &sphere,
            0,
            &ray_x(),
            Interval::clip(0.0, f64::INFINITY),
            &mut out,
        );
        assert!(out.is_empty(), "{out:?}");
    }

    #[test]
    fn intersection_labels_ends_by_the_bounding_operand() {
        let a = [Interval {
            start: 0.0,
            start_by: Boundary::Quadric(0),
            end: 5.0,
            end_by: Boundary::Quadric(0),
        }];
        let b = [
            Interval {
                start: 1.0,
                start_by: Boundary::Quadric(1),
                end: 2.0,
                end_by: Boundary::Quadric(1),
            },
            Interval {
                start: 4.0,
                start_by: Boundary::Quadric(2),
                end: 6.0,
                end_by: Boundary::Quadric(2),
            },
        ];
        let mut out = Vec::new();
        intersect_into(&a, &b, &mut out);
        assert_eq!(out.len(), 2);
        assert_eq!(out[1].start_by, Boundary::Quadric(2));
        assert_eq!(out[1].end_by, Boundary::Quadric(0));
        // Touching intervals meet in a point: regularised away.
        let c = [Interval {
            start: 5.0,
            start_by: Boundary::Quadric(3),
            end: 7.0,
            end_by: Boundary::Quadric(3),
        }];
        intersect_into(&a, &c, &mut out);
        assert!(out.is_empty());
    }

    #[test]
    fn bounds_that_meet_keep_the_first_label_in_either_order() {
        let piece = |start, s, end, e| Interval {
            start,
            start_by: Boundary::Quadric(s),
            end,
            end_by: Boundary::Quadric(e),
        };
        // Two literals on one surface: they begin and end at the very same parameters.
        let low = [piece(1.0, 3, 4.0, 3)];
        let high = [piece(1.0, 8, 4.0, 8), piece(6.0, 8, 7.0, 8)];
        let (mut one, mut other) = (Vec::new(), Vec::new());
        intersect_into(&low, &high, &mut one);
        intersect_into(&high, &low, &mut other);
        assert_eq!(one, other);
        assert_eq!(one, vec![piece(1.0, 3, 4.0, 3)]);
    }
}
