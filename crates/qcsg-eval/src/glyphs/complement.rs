//! The exact complement of a line of text, for engraving: for each cluster of glyphs
//! ([`super::line`]), the cells its glyphs leave unfilled within its strip along the line, cut
//! from the same lines and parabolas as the glyphs' own cells
//! ([`qcsg_mesh::curved::curved_complement_cells`]), and the strip above and below them; then
//! the strips between the clusters and the half-planes before and after them. Every piece of a
//! cluster is built in the cluster's frame, so a cluster the line repeats shares its pieces.
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

use super::layout::control_box;
use super::{Strip, region_node};
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

/// A wall along an axis: the half-plane where coordinate `axis` is at most `value` (`upper`)
/// or at least `value`. The two sides of one value are exact flips of each other, so pieces
/// that meet on a wall share its face exactly.
pub(super) fn axis_wall(
    dag: &mut Dag,
    axis: usize,
    upper: bool,
    value: f64,
    source: Source,
) -> Option<Edge> {
    let unit = if axis == 0 { DVec2::X } else { DVec2::Y };
    let (normal, offset) = if upper {
        (unit, value)
    } else {
        (-unit, -value)
    };
    let q = half_space(&HalfPlane { normal, offset })?;
    Some(dag.leaf(q, source).into())
}

/// The complement of one cluster of glyphs within its strip (its outline's extent along the
/// line), in the cluster's frame.
#[derive(Clone, Copy, Debug)]
pub(super) struct ClusterComplement {
    /// The unfilled cells within the strip, and the strip above and below the partitioned box.
    pub inside: NodeId,
    /// Where the strip begins along the line.
    pub lo: f64,
    /// Where the strip ends along the line.
    pub hi: f64,
}

/// The complement, within its strip along `axis`, of the union of `glyphs` (each a list of
/// contours filled with the non-zero rule); `None` where it cannot be built.
pub(super) fn cluster_complement(
    dag: &mut Dag,
    glyphs: &[Vec<Vec<Segment>>],
    axis: usize,
    source: Source,
) -> Option<ClusterComplement> {
    let mut contours: Vec<Vec<Segment>> = Vec::new();
    for glyph in glyphs {
        if signed_area(glyph) > 0.0 {
            contours.extend(reversed(glyph));
        } else {
            contours.extend(glyph.iter().cloned());
        }
    }
    let (lo, hi) = control_box(&contours);
    let (lo, hi) = (lo[axis], hi[axis]);
    let complement = curved_complement_cells(&contours, FillRule::NonZero).ok()??;
    // The partition's box reaches past the outline; its cells are cut back to the strip, and
    // the strip above and below the box is added, each wall the exact flip of the partition's.
    let (min, max) = (complement.min, complement.max);
    let across = 1 - axis;
    let strip = Strip { axis, lo, hi };
    let mut parts: Vec<Edge> = Vec::with_capacity(3);
    if let Some(cells) = region_node(dag, &complement.region, Some(strip), source).ok()? {
        parts.push(cells.into());
    }
    let inf = f64::INFINITY;
    let below = (true, min[across], -inf, min[across]);
    let above = (false, max[across], max[across], inf);
    for (upper, wall, from, to) in [below, above] {
        let sides = [
            axis_wall(dag, axis, false, lo, source)?,
            axis_wall(dag, axis, true, hi, source)?,
            axis_wall(dag, across, upper, wall, source)?,
        ];
        let node = dag.intersection(sides, source);
        let (mut box_min, mut box_max) = (DVec2::ZERO, DVec2::ZERO);
        (box_min[axis], box_max[axis]) = (lo, hi);
        (box_min[across], box_max[across]) = (from, to);
        parts.push(dag.bounded(node, column(box_min, box_max)).into());
    }
    Some(ClusterComplement {
        inside: dag.union(parts, source),
        lo,
        hi,
    })
}

/// The complement of a line of clusters, each given by its complement within its strip and its
/// frame's origin, in order along `axis` with their strips apart: the clusters' pieces, the
/// strips between them, and the half-planes before the first and after the last.
pub(super) fn outside_clusters(
    dag: &mut Dag,
    clusters: &[(ClusterComplement, DVec2)],
    axis: usize,
    source: Source,
) -> Option<NodeId> {
    let placed_wall = |dag: &mut Dag, upper: bool, value: f64, origin: DVec2| {
        let wall = axis_wall(dag, axis, upper, value, source)?;
        dag.translated(wall, origin.extend(0.0)).ok()
    };
    let (first, last) = (clusters.first()?, clusters.last()?);
    let mut parts: Vec<Edge> = Vec::with_capacity(2 * clusters.len() + 1);
    parts.push(placed_wall(dag, true, first.0.lo, first.1)?);
    for pair in clusters.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        let sides = [
            placed_wall(dag, false, a.0.hi, a.1)?,
            placed_wall(dag, true, b.0.lo, b.1)?,
        ];
        parts.push(dag.intersection(sides, source).into());
    }
    parts.push(placed_wall(dag, false, last.0.hi, last.1)?);
    for (complement, origin) in clusters {
        parts.push(
            dag.translated(complement.inside.into(), origin.extend(0.0))
                .ok()?,
        );
    }
    Some(dag.union(parts, source))
}
