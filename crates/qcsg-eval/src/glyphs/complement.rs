//! The exact complement of a line of text, for engraving: everything outside the text's box, and
//! within it the cells the glyphs leave unfilled, cut from the same lines and parabolas as the
//! glyphs' own cells ([`qcsg_mesh::curved::curved_complement_cells`]).
//!
//! Subtracting text from a part intersects the part with the text's complement. Left to De
//! Morgan, that complement is the product of every glyph cell's complement, which multiplies out
//! past any term limit; recorded with [`Dag::set_complement`], it is instead a union of cells
//! about as many as the glyphs' own, so an engraved name plate has a DNF near-linear in them.
//!
//! The glyphs are united by filling all their contours at once with the non-zero rule. That
//! equals the union of the glyphs filled one by one when every glyph winds the same way, so a glyph
//! that encloses positive area is reversed first (TrueType draws outer contours clockwise).

use glam::DVec2;
use qcsg_csg::{Dag, Edge, NodeId, Source};
use qcsg_mesh::HalfPlane;
use qcsg_mesh::curved::{FillRule, Segment, curved_complement_cells};

use super::region_node;
use crate::polygon::half_space;
use crate::primitives_2d::column;

/// Twice the signed area enclosed by a glyph's contours, arcs counted by their control polygon
/// (which has the arc's orientation).
fn signed_area(contours: &[Vec<Segment>]) -> f64 {
    let cross = |a: DVec2, b: DVec2| a.perp_dot(b);
    contours
        .iter()
        .flatten()
        .map(|s| match *s {
            Segment::Line(a, b) => cross(a, b),
            Segment::Quad(a, c, b) => cross(a, c) + cross(c, b),
        })
        .sum()
}

/// The contours traversed backwards.
fn reversed(contours: &[Vec<Segment>]) -> Vec<Vec<Segment>> {
    contours
        .iter()
        .map(|contour| {
            contour
                .iter()
                .rev()
                .map(|s| match *s {
                    Segment::Line(a, b) => Segment::Line(b, a),
                    Segment::Quad(a, c, b) => Segment::Quad(b, c, a),
                })
                .collect()
        })
        .collect()
}

/// The complement of the union of `glyphs` (each a list of contours filled with the non-zero
/// rule) as a node, or `None` where it cannot be built (the caller then keeps De Morgan's form).
pub fn complement_node(
    dag: &mut Dag,
    glyphs: &[&[Vec<Segment>]],
    source: Source,
) -> Option<NodeId> {
    let mut contours: Vec<Vec<Segment>> = Vec::new();
    for glyph in glyphs {
        if signed_area(glyph) > 0.0 {
            contours.extend(reversed(glyph));
        } else {
            contours.extend(glyph.iter().cloned());
        }
    }
    let complement = curved_complement_cells(&contours, FillRule::NonZero).ok()??;
    let (min, max) = (complement.min, complement.max);
    let inf = f64::INFINITY;
    // Outside the box, in four disjoint pieces: left, right, and below and above between them.
    // Each wall is the exact flip of the partition's wall, so faces on it cancel exactly.
    let wall = |dag: &mut Dag, normal: DVec2, offset: f64| -> Option<Edge> {
        let q = half_space(&HalfPlane { normal, offset })?;
        Some(dag.leaf(q, source).into())
    };
    let mut parts: Vec<Edge> = Vec::with_capacity(5);
    let left = wall(dag, DVec2::X, min.x)?;
    parts.push(
        dag.bounded(
            left.child,
            column(DVec2::new(-inf, -inf), DVec2::new(min.x, inf)),
        )
        .into(),
    );
    let right = wall(dag, -DVec2::X, -max.x)?;
    parts.push(
        dag.bounded(
            right.child,
            column(DVec2::new(max.x, -inf), DVec2::new(inf, inf)),
        )
        .into(),
    );
    let between = [wall(dag, -DVec2::X, -min.x)?, wall(dag, DVec2::X, max.x)?];
    for (normal, offset, lo, hi) in [
        (DVec2::Y, min.y, -inf, min.y),
        (-DVec2::Y, -max.y, max.y, inf),
    ] {
        let side = wall(dag, normal, offset)?;
        let node = dag.intersection([between[0], between[1], side], source);
        parts.push(
            dag.bounded(node, column(DVec2::new(min.x, lo), DVec2::new(max.x, hi)))
                .into(),
        );
    }
    if let Some(cells) = region_node(dag, &complement.region, source).ok()? {
        parts.push(cells.into());
    }
    Some(dag.union(parts, source))
}
