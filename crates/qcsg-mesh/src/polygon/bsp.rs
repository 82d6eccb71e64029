//! The partition of the plane by the polygon's own edge lines, and the even–odd parity carried
//! through it.
//!
//! A binary space partition whose splitting lines are the lines of the edges (an
//! autopartition), taken in a fixed pseudo-random order, which Paterson and Yao showed cuts n
//! segments into O(n log n) fragments in expectation and in practice nearly O(n); every region
//! whose rounded outline has more than [`MAX_SIDES`] sides is first halved by an axis-parallel
//! line, so no region, and so no cell, has more than a few half-planes, and convex runs of many
//! edges (a circle) are split like a kd-tree instead of carving one cell of thousands of sides.
//!
//! Each region holds the edges that may touch it (conservatively) and a reference point whose
//! parity is known. The root's reference point lies outside every edge's box, so its parity is
//! even; a child's reference point is its parent's flipped once per edge crossed on the segment
//! between them, a segment inside the parent's convex region, so only the parent's edges can
//! cross it. A region that no edge touches is wholly inside or outside: a cell if its parity is
//! odd. Splitting by an edge's line takes that edge (and any edge exactly on the line) out of both
//! children, so the partition always progresses; it runs on an explicit stack.

use glam::DVec2;

use super::region::Piece;
use super::{Cell2, Edge, HalfPlane};
use crate::exact::{edges_cross_properly, orient2d, segment_crosses_edge};

/// A region whose rounded outline has more sides than this is halved by an axis-parallel line
/// before anything else.
const MAX_SIDES: usize = 6;

/// A region awaiting its split.
struct Region {
    piece: Piece,
    reference: DVec2,
    parity: bool,
    edges: Vec<u32>,
}

/// The partition's state.
struct Partition<'a> {
    edges: &'a [Edge],
    /// The largest coordinate magnitude, the scale of rounding errors.
    magnitude: f64,
    /// The box of every edge, which holds every region.
    min: DVec2,
    max: DVec2,
    cells: Vec<Cell2>,
    crossing: Option<(usize, usize)>,
}

/// The even–odd region of `edges` as convex cells, and the first pair of properly crossing edges
/// met (if any).
pub(super) fn decompose(edges: &[Edge]) -> (Vec<Cell2>, Option<(usize, usize)>) {
    if edges.is_empty() {
        return (Vec::new(), None);
    }
    let (min, max) = edges.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), e| (lo.min(e.a).min(e.b), hi.max(e.a).max(e.b)),
    );
    if min.x == max.x || min.y == max.y {
        // Every point on one axis-parallel line: no area.
        return (Vec::new(), None);
    }
    let mut partition = Partition {
        edges,
        magnitude: min.abs().max(max.abs()).max_element(),
        min,
        max,
        cells: Vec::new(),
        crossing: None,
    };
    // Outside every edge's box: no crossing on the way to infinity, so even.
    let outside = min - (max - min) * DVec2::new(0.25, 0.375);
    let piece = Piece::from_box(min, max);
    let reference = piece.interior_point();
    let all: Vec<u32> = (0..edges.len() as u32).collect();
    let parity = partition.odd_crossings(outside, reference, &all);
    let root = Region {
        piece,
        reference,
        parity,
        edges: all,
    };
    partition.run(root);
    (partition.cells, partition.crossing)
}

/// The order in which edges split: a fixed scramble of their indices.
fn priority(index: u32) -> u64 {
    let mut z = u64::from(index).wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

impl Partition<'_> {
    /// The rounding tolerance of `line`'s values at points of this polygon's magnitude (it also
    /// covers the rounded line's distance from the exact edge).
    fn tolerance(&self, line: &HalfPlane) -> f64 {
        64.0 * f64::EPSILON
            * ((line.normal.x.abs() + line.normal.y.abs()) * self.magnitude + line.offset.abs())
    }

    /// Whether the segment `p`–`q` crosses an odd number of the edges in `list`.
    fn odd_crossings(&self, p: DVec2, q: DVec2, list: &[u32]) -> bool {
        list.iter()
            .filter(|&&i| {
                let e = &self.edges[i as usize];
                segment_crosses_edge(p, q, e.a, e.b)
            })
            .count()
            % 2
            == 1
    }

    fn run(&mut self, root: Region) {
        let mut stack = vec![root];
        while let Some(region) = stack.pop() {
            if region.piece.vertices.len() > MAX_SIDES {
                let line = self.halving_line(&region.piece);
                // A region too thin to halve is treated as it stands.
                if let Some((low, high)) = region.piece.split(line, self.tolerance(&line)) {
                    stack.extend(self.children(&region, low, high, None));
                    continue;
                }
            }
            if region.edges.is_empty() {
                if region.parity {
                    let pad = 1e-12 * self.magnitude.max(f64::MIN_POSITIVE);
                    self.cells
                        .push(region.piece.into_cell(pad, self.min, self.max));
                }
                continue;
            }
            let splitter = *region
                .edges
                .iter()
                .min_by_key(|&&i| priority(i))
                .expect("a region with edges");
            let line = self.edges[splitter as usize].line;
            match region.piece.split(line, self.tolerance(&line)) {
                Some((low, high)) => {
                    stack.extend(self.children(&region, low, high, Some(splitter)))
                }
                None => {
                    // The edge's line misses the region's interior: so does the edge.
                    let mut region = region;
                    region.edges.retain(|&i| i != splitter);
                    stack.push(region);
                }
            }
        }
    }

    /// An axis-parallel line through the middle of the piece's longer extent.
    fn halving_line(&self, piece: &Piece) -> HalfPlane {
        let (lo, hi) = piece.bounds();
        let middle = 0.5 * (lo + hi);
        if hi.x - lo.x >= hi.y - lo.y {
            HalfPlane {
                normal: DVec2::X,
                offset: middle.x,
            }
        } else {
            HalfPlane {
                normal: DVec2::Y,
                offset: middle.y,
            }
        }
    }

    /// The two children of `parent` cut along an edge's line (`splitter`) or a free line: their
    /// edges, reference points and parities.
    fn children(
        &mut self,
        parent: &Region,
        low: Piece,
        high: Piece,
        splitter: Option<u32>,
    ) -> [Region; 2] {
        // Edges exactly on the splitting edge's line lie on the wall between the children.
        let on_wall = |edge: &Edge| match splitter {
            Some(s) => {
                let s = &self.edges[s as usize];
                orient2d(s.a, s.b, edge.a) == 0 && orient2d(s.a, s.b, edge.b) == 0
            }
            None => false,
        };
        let kept: Vec<u32> = parent
            .edges
            .iter()
            .copied()
            .filter(|&i| !on_wall(&self.edges[i as usize]))
            .collect();
        if let (Some(s), None) = (splitter, self.crossing) {
            let e = self.edges[s as usize];
            if let Some(&f) = kept.iter().find(|&&f| {
                let f = &self.edges[f as usize];
                edges_cross_properly(e.a, e.b, f.a, f.b)
            }) {
                self.crossing = Some((s.min(f) as usize, s.max(f) as usize));
            }
        }
        [low, high].map(|mut piece| {
            piece.prune(|h| self.tolerance(h));
            let edges: Vec<u32> = kept
                .iter()
                .copied()
                .filter(|&i| {
                    let e = &self.edges[i as usize];
                    piece.may_touch(e.a, e.b, |h| self.tolerance(h))
                })
                .collect();
            let reference = piece.interior_point();
            let parity =
                parent.parity ^ self.odd_crossings(parent.reference, reference, &parent.edges);
            Region {
                piece,
                reference,
                parity,
                edges,
            }
        })
    }
}
