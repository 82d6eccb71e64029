//! Abutting terms: two other terms that meet along a plane enter eq. 22 also merged, so that a
//! quadric crossing the plane between them inside both is classified ("Abutting terms" in
//! [`super`]).

use super::half_spaces::{HalfSpace, half_spaces};
use super::view::PARALLEL;
use qcsg_csg::BoxIndex;
use qcsg_quadric::Quadric;

/// Most abutting unions per other term (see "Abutting terms"); a guard against grids of many
/// parts, where the pairs would outnumber the terms by far.
pub(super) const MAX_MERGED_PER_TERM: usize = 4;

/// Index given to literals made here (half-spaces of a slab) until
/// [`Shapes::new`](super::tangency::Shapes::new) numbers them after the DNF's quadrics.
pub(super) const MADE_LITERAL: u32 = u32::MAX;

/// The literals of a term, each with its index in the DNF's quadric table.
pub(super) type TermLiterals = Vec<(u32, Quadric)>;

/// The literals of two terms, minus the two that meet along `shared` (a half-space of `a`'s
/// literal `la` and the opposite one of `b`'s `lb`), with the rest of each of those two put back
/// as half-spaces: a subset of the union of the two terms (see "Abutting terms").
pub(super) fn merged_literals(
    a: &[(u32, Quadric)],
    b: &[(u32, Quadric)],
    (la, lb): (usize, usize),
    (rest_a, rest_b): (&[HalfSpace], &[HalfSpace]),
) -> TermLiterals {
    let keep = |literals: &[(u32, Quadric)], skip: usize| {
        literals
            .iter()
            .enumerate()
            .filter(move |&(j, _)| j != skip)
            .map(|(_, l)| *l)
            .collect::<Vec<_>>()
    };
    let rest = rest_a
        .iter()
        .chain(rest_b)
        .filter_map(|h| Quadric::half_space(h.point, h.normal).map(|q| (MADE_LITERAL, q)));
    let mut out = keep(a, la);
    out.extend(keep(b, lb));
    out.extend(rest);
    out
}

/// For every two terms whose boxes touch and that meet along a plane (one holds `n·x ≤ c`, the
/// other `n·x ≥ c`), the merged term of [`merged_literals`] with the indices of the two, at
/// most `limit` of them, in a fixed order.
pub(super) fn abutting_unions(
    terms: &[TermLiterals],
    boxes: &BoxIndex,
    tolerance: f64,
    limit: usize,
) -> Vec<(TermLiterals, (usize, usize))> {
    let planes: Vec<Vec<Option<Vec<HalfSpace>>>> = terms
        .iter()
        .map(|t| t.iter().map(|(_, q)| half_spaces(q)).collect())
        .collect();
    let opposite = |h: &HalfSpace, g: &HalfSpace| {
        (h.normal + g.normal).length() <= PARALLEL && (h.offset + g.offset).abs() <= tolerance
    };
    let mut out = Vec::new();
    for (i, planes_i) in planes.iter().enumerate() {
        // Terms whose boxes are apart cannot meet along a plane.
        let touching = boxes.near(&boxes.boxes()[i], tolerance);
        for k in touching.into_iter().map(|k| k as usize).filter(|&k| k > i) {
            let planes_k = &planes[k];
            for (la, spaces_a) in planes_i.iter().enumerate() {
                let Some(spaces_a) = spaces_a else { continue };
                for (lb, spaces_b) in planes_k.iter().enumerate() {
                    let Some(spaces_b) = spaces_b else { continue };
                    for (ha, h) in spaces_a.iter().enumerate() {
                        let Some(hb) = spaces_b.iter().position(|g| opposite(h, g)) else {
                            continue;
                        };
                        if out.len() >= limit {
                            return out;
                        }
                        let rest = |spaces: &[HalfSpace], skip: usize| {
                            spaces
                                .iter()
                                .enumerate()
                                .filter(|&(j, _)| j != skip)
                                .map(|(_, h)| *h)
                                .collect::<Vec<_>>()
                        };
                        let (rest_a, rest_b) = (rest(spaces_a, ha), rest(spaces_b, hb));
                        let literals =
                            merged_literals(&terms[i], &terms[k], (la, lb), (&rest_a, &rest_b));
                        out.push((literals, (i, k)));
                    }
                }
            }
        }
    }
    out
}
