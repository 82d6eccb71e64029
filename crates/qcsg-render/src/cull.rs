//! Where a term may hold: a box around the part of its box that no literal is proven to leave
//! out, found by bisection.
//!
//! The compiler's term boxes bound each literal's solid, not their intersection, so a cell of a
//! polygon (the intersection of a few half-spaces, extruded) often keeps a box far larger than
//! itself. Rays that cross that box but not the cell read the term's literals only to find it
//! empty along them. The box found here is used to leave such terms out (for whole squares of
//! pixels, and per ray) — never to clip a ray, whose piece in the term's own box stays what the
//! term's intervals are computed on, so that whatever is read is read exactly as before.

use qcsg_csg::quadric_box::{BoxClass, classify};
use qcsg_csg::{Aabb, Dnf, Term};
use qcsg_quadric::DVec3;

/// Bisections of a term's box: down to 1/2^2 of its size on each axis. Coarse, because a
/// scene of hundreds of terms pays for them at each rebuild.
const SPLITS: u32 = 6;

/// Terms of more literals than this are not bisected (their literals are read where they may
/// fail instead, see [`crate::raytrace::TermIndex`]).
const MOST_LITERALS: usize = 64;

/// A box, within `bounds` (the term's padded box), around the points of `bounds` where `term`
/// may hold, grown like the term boxes so that rounding never leaves out a ray that reaches the
/// term; `None` when it is no smaller than `bounds`, or the term is not bisected.
pub fn where_it_may_hold(dnf: &Dnf, term: &Term, bounds: &Aabb) -> Option<Aabb> {
    if !bounds.is_bounded() || bounds.is_empty() || term.literals.len() > MOST_LITERALS {
        return None;
    }
    let quadrics: Vec<_> = term
        .literals
        .iter()
        .map(|&id| dnf.quadrics.get(id as usize).map(|q| &q.quadric))
        .collect::<Option<_>>()?;
    let all: u64 = if quadrics.len() == 64 {
        u64::MAX
    } else {
        (1 << quadrics.len()) - 1
    };
    let mut found = Aabb::EMPTY;
    // Each piece with the literals not yet proven to hold on all of it.
    let mut stack = vec![(*bounds, 0, all)];
    'pieces: while let Some((piece, depth, open)) = stack.pop() {
        let mut still_open = open;
        for (k, q) in quadrics.iter().enumerate() {
            if open & (1 << k) == 0 {
                continue;
            }
            match classify(q, &piece) {
                BoxClass::Outside => continue 'pieces,
                BoxClass::Inside => still_open &= !(1 << k),
                BoxClass::Cuts => {}
            }
        }
        if still_open != 0 && depth < SPLITS {
            let axis = (piece.max - piece.min).max_position();
            let middle = 0.5 * (piece.min[axis] + piece.max[axis]);
            let (mut low, mut high) = (piece, piece);
            low.max[axis] = middle;
            high.min[axis] = middle;
            stack.push((low, depth + 1, still_open));
            stack.push((high, depth + 1, still_open));
        } else {
            found = found.union(&piece);
        }
    }
    if found.is_empty() {
        // Empty everywhere: a box no ray meets would do, but a point of the term's box is
        // simpler to reason about and costs nothing.
        let c = bounds.centre();
        return Some(Aabb { min: c, max: c });
    }
    let grown = grow(&found);
    let tighter =
        (0..3).any(|axis| grown.min[axis] > bounds.min[axis] || grown.max[axis] < bounds.max[axis]);
    tighter.then_some(grown)
}

/// `b` grown by a small fraction of its size and position on each axis: the term boxes rays
/// test, and the boxes found here, so that rounding never leaves out a ray that reaches a term.
pub(crate) fn grow(b: &Aabb) -> Aabb {
    let pad = |lo: f64, hi: f64| {
        let grow = 1e-7 * ((hi - lo) + lo.abs().max(hi.abs()));
        if grow.is_finite() { grow } else { 0.0 }
    };
    let g = DVec3::new(
        pad(b.min.x, b.max.x),
        pad(b.min.y, b.max.y),
        pad(b.min.z, b.max.z),
    );
    Aabb {
        min: b.min - g,
        max: b.max + g,
    }
}
