//! A line of text as clusters of glyphs that stand apart along it, each built once in its own
//! frame and placed with a translation.
//!
//! A text repeats few glyphs many times. Built where each glyph stands, every repeat is new
//! geometry: hundreds of DAG nodes a glyph. Built about its own origin, a glyph is the same
//! outline to the bit wherever it stands, so the DAG's hash-consing keeps one copy and each
//! repeat costs one edge. Glyphs whose boxes overlap along the line (kerned pairs, a small
//! `spacing`) are built together, in the frame of the first, so that the text's complement
//! can be cut from their outlines at once ([`super::complement`]); the clusters' boxes are
//! then apart, and the complement is a union of one piece per cluster and the strips between
//! them. The line runs along x, or along y where that separates the glyphs better (vertical
//! text).

use std::collections::HashMap;

use glam::DVec2;
use qcsg_csg::{Dag, Edge, NodeId, Source};
use qcsg_mesh::curved::{CurvedError, FillRule, Segment, curved_cells};

use super::complement::{ClusterComplement, cluster_complement, outside_clusters};
use super::layout::{PlacedGlyph, control_box, shifted};
use super::{TextFailure, region_node};

/// How far apart, relative to the size of the coordinates, two boxes must be to be built
/// apart: far more than the rounding of a translated wall, far less than any gap in a font.
const SEPARATION: f64 = 1e-9;

/// Glyphs built together, in the frame of the first.
struct Cluster {
    /// The frame's origin in the text's coordinates.
    origin: DVec2,
    /// The glyphs, by their index in the line, in the line's order.
    glyphs: Vec<usize>,
}

/// A cluster built: its shape and the complement of its shape, both in the cluster's frame.
#[derive(Clone, Copy)]
struct Built {
    shape: Option<NodeId>,
    complement: Option<ClusterComplement>,
}

/// The groups of `boxes` whose extents along `axis` overlap, or come within `tolerance`
/// (transitively), in order along the axis; each group lists its boxes in index order.
fn groups_along(boxes: &[(DVec2, DVec2)], axis: usize, tolerance: f64) -> Vec<Vec<usize>> {
    let mut order: Vec<usize> = (0..boxes.len()).collect();
    order.sort_by(|&a, &b| boxes[a].0[axis].total_cmp(&boxes[b].0[axis]));
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut reach = f64::NEG_INFINITY;
    for i in order {
        let (lo, hi) = boxes[i];
        match groups.last_mut() {
            Some(group) if lo[axis] <= reach + tolerance => group.push(i),
            _ => groups.push(vec![i]),
        }
        reach = reach.max(hi[axis]);
    }
    for group in &mut groups {
        group.sort_unstable();
    }
    groups
}

/// The text's shape (`None` when nothing is drawn) and, where it could be built, its exact
/// complement, from `glyphs` placed in the text's coordinates.
pub(super) fn build_line(
    dag: &mut Dag,
    glyphs: &[PlacedGlyph],
    source: Source,
) -> Result<Option<(NodeId, Option<NodeId>)>, TextFailure> {
    let boxes: Vec<(DVec2, DVec2)> = glyphs
        .iter()
        .map(|g| {
            let (lo, hi) = control_box(&g.contours);
            (lo + g.origin, hi + g.origin)
        })
        .collect();
    let magnitude = boxes
        .iter()
        .map(|(lo, hi)| lo.abs().max(hi.abs()).max_element())
        .fold(0.0, f64::max);
    let tolerance = SEPARATION * magnitude;
    let along_x = groups_along(&boxes, 0, tolerance);
    let along_y = groups_along(&boxes, 1, tolerance);
    let (axis, groups) = if along_y.len() > along_x.len() {
        (1, along_y)
    } else {
        (0, along_x)
    };
    let clusters: Vec<Cluster> = groups
        .into_iter()
        .map(|glyph_indices| Cluster {
            origin: glyphs[glyph_indices[0]].origin,
            glyphs: glyph_indices,
        })
        .collect();

    // Clusters alike (the same glyphs at the same offsets from the first) are built once.
    let mut built: HashMap<Vec<(u16, [u64; 2])>, Built> = HashMap::new();
    let mut shapes: Vec<Edge> = Vec::with_capacity(clusters.len());
    let mut complements: Option<Vec<(ClusterComplement, DVec2)>> =
        Some(Vec::with_capacity(clusters.len()));
    for cluster in &clusters {
        let key = cluster
            .glyphs
            .iter()
            .map(|&i| {
                let offset = glyphs[i].origin - cluster.origin;
                (glyphs[i].id, [offset.x.to_bits(), offset.y.to_bits()])
            })
            .collect::<Vec<_>>();
        let made = match built.get(&key) {
            Some(made) => *made,
            None => {
                let made = build_cluster(dag, glyphs, cluster, axis, source)?;
                built.insert(key, made);
                made
            }
        };
        let place = |dag: &mut Dag, node: NodeId| {
            dag.translated(node.into(), cluster.origin.extend(0.0))
                .map_err(|_| TextFailure {
                    argument: "size",
                    message: "the text's position is not a finite number".into(),
                    limit: false,
                })
        };
        // A cluster that draws nothing leaves its strip to the strips around it.
        let Some(shape) = made.shape else {
            continue;
        };
        shapes.push(place(dag, shape)?);
        complements = match (complements, made.complement) {
            (Some(mut list), Some(complement)) => {
                list.push((complement, cluster.origin));
                Some(list)
            }
            _ => None,
        };
    }
    let shape = match shapes.len() {
        0 => return Ok(None),
        1 if shapes[0].transform == qcsg_csg::TransformId::IDENTITY => shapes[0].child,
        _ => dag.union(shapes, source),
    };
    let complement = complements.and_then(|list| outside_clusters(dag, &list, axis, source));
    Ok(Some((shape, complement)))
}

/// One cluster's shape (its glyphs, each filled with the non-zero rule, united) and its
/// complement, in the frame of its first glyph.
fn build_cluster(
    dag: &mut Dag,
    glyphs: &[PlacedGlyph],
    cluster: &Cluster,
    axis: usize,
    source: Source,
) -> Result<Built, TextFailure> {
    let mut outlines: Vec<Vec<Vec<Segment>>> = Vec::with_capacity(cluster.glyphs.len());
    let mut parts: Vec<Edge> = Vec::with_capacity(cluster.glyphs.len());
    for &i in &cluster.glyphs {
        let glyph = &glyphs[i];
        let offset = glyph.origin - cluster.origin;
        let contours = if offset == DVec2::ZERO {
            glyph.contours.clone()
        } else {
            shifted(&glyph.contours, offset)
        };
        let region = curved_cells(&contours, FillRule::NonZero).map_err(|e| TextFailure {
            argument: if e == CurvedError::BadPoint {
                "size"
            } else {
                "font"
            },
            message: format!("the glyph at byte {} of the text: {e}", glyph.cluster),
            limit: false,
        })?;
        if let Some(node) = region_node(dag, &region, None, source).map_err(|m| TextFailure {
            argument: "size",
            message: m,
            limit: false,
        })? {
            parts.push(node.into());
            outlines.push(contours);
        }
    }
    let shape = match parts.len() {
        0 => None,
        1 => Some(parts[0].child),
        _ => Some(dag.union(parts, source)),
    };
    let complement = match shape {
        Some(_) => cluster_complement(dag, &outlines, axis, source),
        None => None,
    };
    Ok(Built { shape, complement })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn boxes(spans: &[(f64, f64)]) -> Vec<(DVec2, DVec2)> {
        spans
            .iter()
            .map(|&(lo, hi)| (DVec2::new(lo, 0.0), DVec2::new(hi, 1.0)))
            .collect()
    }

    #[test]
    fn overlapping_boxes_are_grouped_and_apart_ones_are_not() {
        let line = boxes(&[(0.0, 1.0), (1.5, 2.5), (2.4, 3.0), (5.0, 6.0), (0.5, 0.7)]);
        assert_eq!(
            groups_along(&line, 0, 1e-9),
            vec![vec![0, 4], vec![1, 2], vec![3]]
        );
        // Along y every box overlaps every other.
        assert_eq!(groups_along(&line, 1, 1e-9), vec![vec![0, 1, 2, 3, 4]]);
    }

    #[test]
    fn boxes_closer_than_the_tolerance_are_grouped() {
        let line = boxes(&[(0.0, 1.0), (1.0 + 1e-12, 2.0), (2.1, 3.0)]);
        assert_eq!(groups_along(&line, 0, 1e-9), vec![vec![0, 1], vec![2]]);
    }
}
