//! Literals on a sampled plane ("Planar sections", "One side of a slab", "Strips of no width" in
//! [`super`]): a literal's section by the sheet, extruded along its normal ([`section`]), the
//! side of a slab a term holds, and half-spaces of term `a` that leave it no area on the sheet.

use super::half_spaces::{HalfSpace, PlanarParts, beyond, planar_parts};
use super::sheet_views::Refined;
use super::view::PARALLEL;
use qcsg_csg::Aabb;
use qcsg_quadric::{DVec3, Quadric};

/// The section of `literal` by the sheet plane `plane`, as a quadric constant along the
/// plane's normal, with its half-spaces when it is planar: a cylinder cut along its axis gives
/// the slab between the two lines, another plane its line (a half-space across the sheet), a
/// cone or a ball its circle (a cylinder). On the plane it equals the literal, and off it its
/// distance to its surface is the distance within the plane, so it stands for the literal in
/// eq. 22 at points of the sheet (see "Planar sections"). With `P = I − n nᵀ` and the
/// literal's origin moved onto the plane by `δ = t n`: `A' = P A P`, `l' = P (A δ + l)`,
/// `j' = δᵀ A δ + 2 l·δ + j`.
///
/// Planar means `A'` of rank at most one, `λ u uᵀ`, with `l'` along `u`. Rounding leaves noise
/// in the other directions (a cylinder cut exactly along its axis after a rotation), which
/// would make the section a parabolic cylinder with its vertex at `10³¹`: parts below
/// [`SECTION_NOISE`] of the section's scale are dropped, which moves its surface by about that
/// fraction of the scene. `None` for a plane within [`SECTION_TILT`] of parallel to the sheet.
pub(super) fn section(
    literal: &Quadric,
    plane: &HalfSpace,
) -> Option<(Quadric, Option<PlanarParts>)> {
    let n = plane.normal;
    let origin = literal.origin();
    let delta = (plane.offset - n.dot(origin)) * n;
    let rows = literal.matrix_a().map(DVec3::from);
    let a = |v: DVec3| DVec3::new(rows[0].dot(v), rows[1].dot(v), rows[2].dot(v));
    let project = |v: DVec3| v - n.dot(v) * n;
    // P A P, column by column: P A P e_k (symmetric, so also its rows).
    let columns = [DVec3::X, DVec3::Y, DVec3::Z].map(|e| project(a(project(e))));
    let matrix_of = |c: &[DVec3; 3]| [0, 1, 2].map(|r| [c[0][r], c[1][r], c[2][r]]);
    let norm = |m: &[DVec3; 3]| m.iter().map(|c| c.length_squared()).sum::<f64>().sqrt();
    let (a_norm, section_norm) = (norm(&rows), norm(&columns));
    let l = literal.linear();
    let linear = project(a(delta) + l);
    let constant = delta.dot(a(delta)) + 2.0 * l.dot(delta) + literal.constant();
    let at = origin + delta;
    let planar = |matrix: &[[f64; 3]; 3], linear: DVec3| {
        let section = Quadric::from_matrix(at, matrix, linear, constant)?;
        planar_parts(&section).map(|parts| (section, Some(parts)))
    };
    if section_norm <= SECTION_NOISE * a_norm {
        // Linear on the plane: a line, unless the literal is (nearly) parallel to the plane,
        // where `l'` is rounding noise and its line could lie anywhere ("Shared planes" handles
        // planes parallel to the sheet).
        let significant = if a_norm > 0.0 {
            l.length() + (constant.abs() * a_norm).sqrt()
        } else {
            l.length()
        };
        if linear.length() <= SECTION_TILT * significant || linear.length().is_nan() {
            return None;
        }
        return planar(&[[0.0; 3]; 3], linear);
    }
    // Rank one: every column is a multiple of `u`, the longest one's direction.
    let longest = columns
        .iter()
        .copied()
        .max_by(|p, q| p.length_squared().total_cmp(&q.length_squared()))?;
    let u = longest.try_normalize()?;
    let lambda = u.dot(columns[0] * u.x + columns[1] * u.y + columns[2] * u.z);
    let rest: f64 = columns
        .iter()
        .zip([u.x, u.y, u.z])
        .map(|(c, u_k)| (*c - lambda * u_k * u).length_squared())
        .sum::<f64>()
        .sqrt();
    if rest <= SECTION_NOISE * section_norm {
        let across = linear - linear.dot(u) * u;
        let scale = (constant.abs() / section_norm).sqrt();
        if across.length() <= SECTION_NOISE * (linear.length() + section_norm * scale) {
            let rank_one = [0, 1, 2].map(|r| [0, 1, 2].map(|c| lambda * u[r] * u[c]));
            if let Some(found) = planar(&rank_one, linear - across) {
                return Some(found);
            }
        }
    }
    // A conic: an ellipse, a hyperbola or a parabola on the plane.
    let section = Quadric::from_matrix(at, &matrix_of(&columns), linear, constant)?;
    Some((section, None))
}

/// Relative size below which [`section`] takes a part of a section for rounding.
pub(super) const SECTION_NOISE: f64 = 1e-12;

/// Sine of the smallest angle between a planar literal and the sheet that [`section`] replaces
/// by its line on the sheet: closer to parallel, the line's position would be mostly
/// rounding, and the literal stays as it is.
pub(super) const SECTION_TILT: f64 = 1e-6;

/// The half-space that the outside of a slab (its `parts`) is within `bounds`, when `bounds`
/// lies on the inner side of one of the slab's planes, up to `tolerance`: only the half-space
/// beyond the other plane is left there, but for a layer thinner than the tolerance, as where
/// a cut is flush with a face of the part it cuts.
pub(super) fn one_side(
    parts: Option<&PlanarParts>,
    bounds: &Aabb,
    tolerance: f64,
) -> Option<HalfSpace> {
    let Some((spaces, true)) = parts else {
        return None;
    };
    let reach = |n: DVec3| {
        bounds
            .corners()
            .iter()
            .map(|c| n.dot(*c))
            .fold(f64::NEG_INFINITY, f64::max)
    };
    match spaces.as_slice() {
        [a, b] if reach(a.normal) <= a.offset + tolerance => Some(beyond(b)),
        [a, b] if reach(b.normal) <= b.offset + tolerance => Some(beyond(a)),
        _ => None,
    }
}

/// On a sampled `plane`, the outsides of slabs among term `a`'s literals `own` where one side
/// leaves the term no area within its `bounds` (it faces the term's half-spaces across a strip
/// no wider than `tolerance`) stand as their other side, as "One side of a slab" does where
/// the term's box shows it, but for a box that spans both planes of a turned slab. `true` when
/// neither side leaves any: the term has no area on the plane ("Strips of no width").
pub(super) fn one_side_with_area(
    own: &mut [Refined],
    plane: &HalfSpace,
    bounds: &Aabb,
    tolerance: f64,
) -> bool {
    let sides = own_half_spaces(own, Some(plane));
    let has_area = |h: HalfSpace| {
        let mut with = sides.clone();
        with.push(h);
        !no_area_between(&with, plane, bounds, tolerance)
    };
    for r in own.iter_mut() {
        let Some((spaces, true)) = &r.parts else {
            continue;
        };
        let [a, b] = spaces.as_slice() else {
            continue;
        };
        let (a, b) = (beyond(a), beyond(b));
        let half = match (has_area(a), has_area(b)) {
            (false, false) => return true,
            (true, false) => a,
            (false, true) => b,
            (true, true) => continue,
        };
        *r = Refined::one_side(r.index, half, r.quadric, None);
    }
    false
}

/// The half-spaces of term `a`'s planar literals (not the outsides of slabs), but for those
/// parallel to the sampled `plane`, which "Shared planes" handles.
pub(super) fn own_half_spaces(own: &[Refined], plane: Option<&HalfSpace>) -> Vec<HalfSpace> {
    own.iter()
        .filter_map(|r| match &r.parts {
            Some((spaces, false)) => Some(spaces.iter().copied()),
            _ => None,
        })
        .flatten()
        .filter(|h| plane.is_none_or(|p| h.normal.cross(p.normal).length() > PARALLEL))
        .collect()
}

/// Whether two of term `a`'s half-spaces `sides` meet the sampled `plane` in half-planes facing
/// each other across a strip no wider than `tolerance` within the term's `bounds`: the term has
/// no area on the plane ("Strips of no width"). A gusset cut off by a 45° box: the cutter's two
/// faces meet on the gusset's bottom plane, and the DNF term of the face that misses the
/// gusset leaves only the line where they meet.
pub(super) fn no_area_between(
    sides: &[HalfSpace],
    plane: &HalfSpace,
    bounds: &Aabb,
    tolerance: f64,
) -> bool {
    // `n · x ≤ c` on the plane `p · x = o` is `m · x ≤ (c − (n · p) o) / |m'|`, `m = m' / |m'|`
    // with `m' = n − (n · p) p` its normal within the plane.
    let sections: Vec<(DVec3, f64)> = sides
        .iter()
        .filter_map(|h| {
            let across = h.normal.dot(plane.normal);
            let within = h.normal - across * plane.normal;
            let length = within.length();
            (length > PARALLEL)
                .then(|| (within / length, (h.offset - across * plane.offset) / length))
        })
        .collect();
    let corners = bounds.corners();
    sections.iter().enumerate().any(|(i, &(m1, c1))| {
        sections[i + 1..].iter().any(|&(m2, c2)| {
            // Depth inside both half-planes is at most half the sum of the two depths, which is
            // linear in `x`: its largest value over the box is at a corner.
            m1.dot(m2) < 0.0
                && corners
                    .iter()
                    .all(|&x| c1 - m1.dot(x) + c2 - m2.dot(x) <= 2.0 * tolerance)
        })
    })
}

/// A planar literal of another term without the half-spaces that term `a` holds too (see
/// "Literals of both terms"): a slab sharing one side with term `a` becomes its other side, a
/// planar literal whose relation to the sheet the point test decides; `None` where the literal
/// stays whole.
pub(super) fn without_own_sides(
    literal: &Refined,
    own_sides: &[HalfSpace],
    tolerance: f64,
) -> Option<Vec<Quadric>> {
    let Some((spaces, false)) = &literal.parts else {
        return None;
    };
    let shared = |h: &HalfSpace| {
        own_sides.iter().any(|g| {
            (h.normal - g.normal).length() <= PARALLEL && (h.offset - g.offset).abs() <= tolerance
        })
    };
    if !spaces.iter().any(shared) {
        return None;
    }
    let halves = spaces.iter().filter(|h| !shared(h));
    Some(
        halves
            .filter_map(|h| Quadric::half_space(h.point, h.normal))
            .collect(),
    )
}
