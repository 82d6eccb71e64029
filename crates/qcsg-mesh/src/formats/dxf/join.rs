//! Joining segments, arcs and elliptic arcs end to end into paths, as OpenSCAD 2021.01 joins them.
//!
//! End points are matched on a grid: a point falls in the cell `round(p / res)`, or, when that
//! cell is empty, in the nearest occupied neighbouring cell (OpenSCAD's `Grid2d::align`); points
//! in one cell are one vertex. OpenSCAD's `res` is 1/1024; here it is that or, for a drawing
//! under 1/16 unit across, its extent / 64, so that tiny drawings do not collapse into a few
//! cells (OpenSCAD's grid merges every point of a drawing under a thousandth across). Where OpenSCAD
//! moves each point to its cell's corner, a vertex here keeps the exact coordinates of the first
//! point that fell in its cell, so the edges of a path meet exactly.
//!
//! The walk is OpenSCAD's: first chains from end points no other edge touches (open paths, which
//! OpenSCAD closes with a straight edge; here also a warning), then loops from the remaining edges
//! in file order; at each vertex the walk continues along the first unused edge there.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

use glam::DVec2;

use super::parse::Piece;
use super::{Arc, Drawing, DrawingPath, DrawingWarning, Edge, EllipticArc};

/// OpenSCAD's `GRID_COARSE`.
const GRID: f64 = 1.0 / 1024.0;

struct Grid {
    res: f64,
    cells: HashMap<(i64, i64), usize>,
    vertices: Vec<DVec2>,
}

impl Grid {
    fn key(&self, p: DVec2) -> (i64, i64) {
        // `as` saturates: a far point lands in an edge cell rather than wrapping.
        (
            (p.x / self.res).round() as i64,
            (p.y / self.res).round() as i64,
        )
    }

    fn align(&mut self, p: DVec2) -> usize {
        let key = self.key(p);
        if let Some(&v) = self.cells.get(&key) {
            return v;
        }
        let mut best: Option<(i64, usize)> = None;
        for dx in -1..=1i64 {
            for dy in -1..=1i64 {
                let k = (key.0.saturating_add(dx), key.1.saturating_add(dy));
                if let Some(&v) = self.cells.get(&k) {
                    let d = dx.abs() + dy.abs();
                    if best.is_none_or(|(bd, _)| d < bd) {
                        best = Some((d, v));
                    }
                }
            }
        }
        if let Some((_, v)) = best {
            return v;
        }
        let v = self.vertices.len();
        self.vertices.push(p);
        self.cells.insert(key, v);
        v
    }
}

/// An edge between two grid vertices.
struct Link {
    ends: [usize; 2],
    arc: Option<Arc>,
    ellipse: Option<EllipticArc>,
    line: usize,
}

/// Joins `pieces` (segments, arcs and elliptic arcs only) into the drawing's paths.
pub(super) fn join(pieces: &[Piece], drawing: &mut Drawing) {
    let mut lo = DVec2::splat(f64::INFINITY);
    let mut hi = DVec2::splat(f64::NEG_INFINITY);
    for piece in pieces {
        if let Piece::Segment { from, to, .. }
        | Piece::Arc { from, to, .. }
        | Piece::EllipticArc { from, to, .. } = piece
        {
            lo = lo.min(from.min(*to));
            hi = hi.max(from.max(*to));
        }
    }
    let extent = (hi - lo).max_element();
    let res = if extent.is_finite() && extent > 0.0 {
        GRID.min(extent / 64.0)
    } else {
        GRID
    };
    let mut grid = Grid {
        res,
        cells: HashMap::new(),
        vertices: Vec::new(),
    };
    let mut links = Vec::new();
    for piece in pieces {
        let (from, to, arc, ellipse, line) = match *piece {
            Piece::Segment { from, to, line } => (from, to, None, None, line),
            Piece::EllipticArc {
                from,
                to,
                center,
                axes,
                forward,
                line,
            } => (
                from,
                to,
                None,
                Some(EllipticArc {
                    center,
                    axes,
                    forward,
                }),
                line,
            ),
            Piece::Arc {
                from,
                to,
                center,
                radius,
                ccw,
                line,
            } => (
                from,
                to,
                Some(Arc {
                    center,
                    radius,
                    ccw,
                }),
                None,
                line,
            ),
            _ => continue,
        };
        let ends = [grid.align(from), grid.align(to)];
        // An edge inside one cell joins nothing and bounds nothing.
        if ends[0] != ends[1] {
            links.push(Link {
                ends,
                arc,
                ellipse,
                line,
            });
        }
    }
    let mut at: Vec<Vec<usize>> = vec![Vec::new(); grid.vertices.len()];
    for (i, link) in links.iter().enumerate() {
        at[link.ends[0]].push(i);
        at[link.ends[1]].push(i);
    }
    let mut walker = Walker {
        links: &links,
        at: &at,
        vertices: &grid.vertices,
        used: vec![false; links.len()],
        free: at.iter().map(Vec::len).collect(),
        next_at: vec![0; at.len()],
        down_to_one: Vec::new(),
    };
    // Open chains first: from an end no other unused edge touches, the lowest such edge first,
    // as OpenSCAD's scan from the start finds it. Edges are scanned once in order; one passed
    // over can only become a start when its end is left with it alone (`free` falls to 1), and
    // is then queued, so the whole search is linear.
    let mut cursor = 0;
    let mut queued: BinaryHeap<Reverse<usize>> = BinaryHeap::new();
    loop {
        let i = match queued.peek() {
            Some(&Reverse(q)) if q < cursor => {
                queued.pop();
                q
            }
            _ if cursor < links.len() => {
                cursor += 1;
                cursor - 1
            }
            _ => break,
        };
        if walker.used[i] {
            continue;
        }
        let Some(j) = (0..2).find(|&j| walker.free[links[i].ends[j]] == 1) else {
            continue;
        };
        let edges = walker.walk(i, j);
        push_path(drawing, edges, false);
        for v in std::mem::take(&mut walker.down_to_one) {
            if let Some(k) = walker.next_unused(v)
                && k < cursor
            {
                queued.push(Reverse(k));
            }
        }
    }
    // Then loops, from the remaining edges in file order.
    for i in 0..links.len() {
        if walker.used[i] {
            continue;
        }
        let edges = walker.walk(i, 0);
        let closed = edges.first().map(|e| e.from) == edges.last().map(|e| e.to);
        push_path(drawing, edges, closed);
    }
}

fn push_path(drawing: &mut Drawing, mut edges: Vec<Edge>, closed: bool) {
    let (Some(first), Some(last)) = (edges.first().copied(), edges.last().copied()) else {
        return;
    };
    if edges.len() == 1 && first.arc.is_none() && first.ellipse.is_none() {
        drawing.two_point_chains.push([first.from, first.to]);
    }
    if !closed {
        drawing
            .warnings
            .push(DrawingWarning::OpenPath { line: first.line });
        edges.push(Edge {
            from: last.to,
            to: first.from,
            arc: None,
            ellipse: None,
            line: 0,
        });
    }
    drawing.paths.push(DrawingPath {
        edges,
        closed_in_file: closed,
    });
}

struct Walker<'a> {
    links: &'a [Link],
    at: &'a [Vec<usize>],
    vertices: &'a [DVec2],
    used: Vec<bool>,
    /// The unused edges at each vertex.
    free: Vec<usize>,
    /// Where the search for an unused edge at each vertex resumes (edges before it are used).
    next_at: Vec<usize>,
    /// Vertices whose unused edges fell to one during the last walk.
    down_to_one: Vec<usize>,
}

impl Walker<'_> {
    /// The first unused edge at vertex `v`, in the order edges reached it.
    fn next_unused(&mut self, v: usize) -> Option<usize> {
        let list = &self.at[v];
        while self.next_at[v] < list.len() && self.used[list[self.next_at[v]]] {
            self.next_at[v] += 1;
        }
        list.get(self.next_at[v]).copied()
    }

    fn mark_used(&mut self, i: usize) {
        self.used[i] = true;
        for v in self.links[i].ends {
            self.free[v] -= 1;
            if self.free[v] == 1 {
                self.down_to_one.push(v);
            }
        }
    }

    /// Follows unused edges from end `j` of edge `i` until none continues.
    fn walk(&mut self, mut i: usize, mut j: usize) -> Vec<Edge> {
        let mut edges = Vec::new();
        loop {
            let link = &self.links[i];
            let (a, b) = (link.ends[j], link.ends[1 - j]);
            let arc = link.arc.map(|arc| Arc {
                ccw: if j == 0 { arc.ccw } else { !arc.ccw },
                ..arc
            });
            let ellipse = link.ellipse.map(|e| EllipticArc {
                forward: if j == 0 { e.forward } else { !e.forward },
                ..e
            });
            edges.push(Edge {
                from: self.vertices[a],
                to: self.vertices[b],
                arc,
                ellipse,
                line: link.line,
            });
            self.mark_used(i);
            let Some(k) = self.next_unused(b) else { break };
            i = k;
            j = if self.links[k].ends[0] == b { 0 } else { 1 };
        }
        edges
    }
}
