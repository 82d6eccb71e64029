//! Convex regions of the partition: exact half-planes plus rounded corners.
//!
//! A piece is a convex polygon (its vertices rounded, used only to decide sides, bounds and
//! interior points) and the exact half-planes whose intersection it is: the root box's walls and,
//! for each line that cut it, the side it lies on. A line whose rounded distances put every vertex
//! within its tolerance of one side does not cut the piece (the sliver it would cut off is below
//! rounding).

use glam::DVec2;

use super::{Cell2, HalfPlane};

/// A convex region of the partition.
pub(super) struct Piece {
    /// The rounded corners, counter-clockwise.
    pub(super) vertices: Vec<DVec2>,
    /// The half-planes whose intersection is the piece.
    pub(super) planes: Vec<HalfPlane>,
}

impl Piece {
    /// The box `[min, max]` as a piece bounded by its four walls.
    pub(super) fn from_box(min: DVec2, max: DVec2) -> Self {
        Self {
            vertices: vec![min, DVec2::new(max.x, min.y), max, DVec2::new(min.x, max.y)],
            planes: box_walls(min, max),
        }
    }

    /// The mean of the corners: a point strictly inside a piece that has area.
    pub(super) fn interior_point(&self) -> DVec2 {
        self.vertices.iter().sum::<DVec2>() / self.vertices.len() as f64
    }

    /// The two pieces on either side of `line`, or `None` when the line does not cut this one
    /// (every corner within `tolerance` of one side).
    pub(super) fn split(&self, line: HalfPlane, tolerance: f64) -> Option<(Piece, Piece)> {
        let values: Vec<f64> = self.vertices.iter().map(|&v| line.value(v)).collect();
        let inside = values.iter().any(|&d| d < -tolerance);
        let outside = values.iter().any(|&d| d > tolerance);
        if !(inside && outside) {
            return None;
        }
        let mut below = Vec::with_capacity(self.vertices.len() + 1);
        let mut above = Vec::with_capacity(self.vertices.len() + 1);
        let n = self.vertices.len();
        for i in 0..n {
            let (v, w) = (self.vertices[i], self.vertices[(i + 1) % n]);
            let (dv, dw) = (values[i], values[(i + 1) % n]);
            if dv <= tolerance {
                below.push(v);
            }
            if dv >= -tolerance {
                above.push(v);
            }
            if (dv < -tolerance && dw > tolerance) || (dv > tolerance && dw < -tolerance) {
                let crossing = v + (w - v) * (dv / (dv - dw));
                below.push(crossing);
                above.push(crossing);
            }
        }
        let mut below_planes = self.planes.clone();
        below_planes.push(line);
        let mut above_planes = self.planes.clone();
        above_planes.push(line.flipped());
        Some((
            Piece {
                vertices: below,
                planes: below_planes,
            },
            Piece {
                vertices: above,
                planes: above_planes,
            },
        ))
    }

    /// Drops the half-planes that no side of the piece lies on: a half-plane of a convex polygon
    /// is needed only where its line holds two corners (within four times its tolerance); one
    /// that touches a single corner (lines through a fan's apex) or none is redundant.
    pub(super) fn prune(&mut self, tolerance: impl Fn(&HalfPlane) -> f64) {
        let vertices = &self.vertices;
        self.planes.retain(|h| {
            let clearance = 4.0 * tolerance(h);
            vertices
                .iter()
                .filter(|&&v| h.value(v) >= -clearance)
                .count()
                >= 2
        });
    }

    /// The corners' box.
    pub(super) fn bounds(&self) -> (DVec2, DVec2) {
        self.vertices.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), &v| (lo.min(v), hi.max(v)),
        )
    }

    /// The piece as a cell whose box is the corners' padded by `pad`, within the box
    /// `[min, max]` that holds the whole partition.
    pub(super) fn into_cell(self, pad: f64, min: DVec2, max: DVec2) -> Cell2 {
        let (lo, hi) = self.bounds();
        Cell2 {
            half_planes: self.planes,
            min: (lo - pad).max(min),
            max: (hi + pad).min(max),
        }
    }

    /// Whether the segment `a`–`b` may touch the closed piece: a clip of the segment by the
    /// half-planes, each widened by its tolerance, leaves something (never false when it touches).
    pub(super) fn may_touch(
        &self,
        a: DVec2,
        b: DVec2,
        tolerance: impl Fn(&HalfPlane) -> f64,
    ) -> bool {
        let (mut enter, mut exit) = (0.0_f64, 1.0_f64);
        for h in &self.planes {
            let slack = tolerance(h);
            let (va, vb) = (h.value(a) - slack, h.value(b) - slack);
            match (va > 0.0, vb > 0.0) {
                (true, true) => return false,
                (false, false) => {}
                (true, false) => enter = enter.max(va / (va - vb)),
                (false, true) => exit = exit.min(va / (va - vb)),
            }
        }
        enter <= exit + 1e-9
    }
}

/// The four walls of the box `[min, max]`, as exact half-planes.
pub(super) fn box_walls(min: DVec2, max: DVec2) -> Vec<HalfPlane> {
    vec![
        HalfPlane {
            normal: DVec2::new(-1.0, 0.0),
            offset: -min.x,
        },
        HalfPlane {
            normal: DVec2::new(1.0, 0.0),
            offset: max.x,
        },
        HalfPlane {
            normal: DVec2::new(0.0, -1.0),
            offset: -min.y,
        },
        HalfPlane {
            normal: DVec2::new(0.0, 1.0),
            offset: max.y,
        },
    ]
}
