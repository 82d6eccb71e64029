//! Convex polytopes of the 3-D partition: exact planes plus rounded face polygons.
//!
//! A polytope is its faces, each an exact [`Plane`] and the rounded corners of the face polygon
//! in cyclic order. The corners serve only to decide sides, bounds and interior points; the cell
//! is the intersection of the planes. A plane whose rounded values put every corner within its
//! tolerance of one side does not cut the polytope.

use glam::DVec3;

use super::{Cell3, Plane};

/// One face of a convex polytope.
#[derive(Clone, Debug)]
struct Face {
    plane: Plane,
    corners: Vec<DVec3>,
}

/// A convex region of the partition.
#[derive(Clone, Debug)]
pub(super) struct Polytope {
    faces: Vec<Face>,
}

/// The point where segment `v`–`w` meets the plane, from the values `dv`, `dw` of opposite
/// signs; computed from the lexicographically smaller end so both faces sharing the segment get
/// the same point bit for bit.
fn crossing(v: DVec3, w: DVec3, dv: f64, dw: f64) -> DVec3 {
    let ordered = (v.x, v.y, v.z) <= (w.x, w.y, w.z);
    let (v, w, dv, dw) = if ordered {
        (v, w, dv, dw)
    } else {
        (w, v, dw, dv)
    };
    v + (w - v) * (dv / (dv - dw))
}

impl Polytope {
    /// The box `[min, max]` bounded by its six walls.
    pub(super) fn from_box(min: DVec3, max: DVec3) -> Self {
        let corner = |x: bool, y: bool, z: bool| {
            DVec3::new(
                if x { max.x } else { min.x },
                if y { max.y } else { min.y },
                if z { max.z } else { min.z },
            )
        };
        let wall = |normal: DVec3, offset: f64, corners: [DVec3; 4]| Face {
            plane: Plane { normal, offset },
            corners: corners.to_vec(),
        };
        let (f, t) = (false, true);
        Self {
            faces: vec![
                wall(
                    DVec3::NEG_X,
                    -min.x,
                    [
                        corner(f, f, f),
                        corner(f, t, f),
                        corner(f, t, t),
                        corner(f, f, t),
                    ],
                ),
                wall(
                    DVec3::X,
                    max.x,
                    [
                        corner(t, f, f),
                        corner(t, t, f),
                        corner(t, t, t),
                        corner(t, f, t),
                    ],
                ),
                wall(
                    DVec3::NEG_Y,
                    -min.y,
                    [
                        corner(f, f, f),
                        corner(t, f, f),
                        corner(t, f, t),
                        corner(f, f, t),
                    ],
                ),
                wall(
                    DVec3::Y,
                    max.y,
                    [
                        corner(f, t, f),
                        corner(t, t, f),
                        corner(t, t, t),
                        corner(f, t, t),
                    ],
                ),
                wall(
                    DVec3::NEG_Z,
                    -min.z,
                    [
                        corner(f, f, f),
                        corner(t, f, f),
                        corner(t, t, f),
                        corner(f, t, f),
                    ],
                ),
                wall(
                    DVec3::Z,
                    max.z,
                    [
                        corner(f, f, t),
                        corner(t, f, t),
                        corner(t, t, t),
                        corner(f, t, t),
                    ],
                ),
            ],
        }
    }

    /// How many faces (and so planes) bound the polytope.
    pub(super) fn face_count(&self) -> usize {
        self.faces.len()
    }

    /// Every face's corners (a corner shared by faces appears once per face).
    pub(super) fn corners(&self) -> impl Iterator<Item = DVec3> + '_ {
        self.faces.iter().flat_map(|f| f.corners.iter().copied())
    }

    /// The mean of the face corners: a point strictly inside a polytope with volume.
    pub(super) fn interior_point(&self) -> DVec3 {
        let (sum, count) = self
            .faces
            .iter()
            .flat_map(|f| f.corners.iter())
            .fold((DVec3::ZERO, 0usize), |(s, n), &c| (s + c, n + 1));
        sum / count.max(1) as f64
    }

    /// The corners' box.
    pub(super) fn bounds(&self) -> (DVec3, DVec3) {
        self.faces.iter().flat_map(|f| f.corners.iter()).fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), &c| (lo.min(c), hi.max(c)),
        )
    }

    /// Whether the triangle may touch the closed polytope: the triangle clipped by every face
    /// plane, each widened by its tolerance, leaves something (never false when it touches).
    pub(super) fn may_touch(
        &self,
        triangle: [DVec3; 3],
        tolerance: impl Fn(&Plane) -> f64,
    ) -> bool {
        let mut polygon: Vec<DVec3> = triangle.to_vec();
        let mut next: Vec<DVec3> = Vec::with_capacity(8);
        for face in &self.faces {
            let slack = tolerance(&face.plane);
            let values: Vec<f64> = polygon
                .iter()
                .map(|&v| face.plane.value(v) - slack)
                .collect();
            if values.iter().all(|&d| d <= 0.0) {
                continue;
            }
            if values.iter().all(|&d| d > 0.0) {
                return false;
            }
            next.clear();
            let n = polygon.len();
            for i in 0..n {
                let (v, w) = (polygon[i], polygon[(i + 1) % n]);
                let (dv, dw) = (values[i], values[(i + 1) % n]);
                if dv <= 0.0 {
                    next.push(v);
                }
                if (dv <= 0.0) != (dw <= 0.0) {
                    next.push(v + (w - v) * (dv / (dv - dw)));
                }
            }
            std::mem::swap(&mut polygon, &mut next);
        }
        true
    }

    /// The two polytopes on either side of `plane` (below: `normal · p ≤ offset`), or `None` when
    /// the plane does not cut this one.
    pub(super) fn split(&self, plane: Plane, tolerance: f64) -> Option<(Polytope, Polytope)> {
        let values: Vec<Vec<f64>> = self
            .faces
            .iter()
            .map(|f| f.corners.iter().map(|&c| plane.value(c)).collect())
            .collect();
        let below_any = values.iter().flatten().any(|&d| d < -tolerance);
        let above_any = values.iter().flatten().any(|&d| d > tolerance);
        if !(below_any && above_any) {
            return None;
        }
        let mut below = Vec::with_capacity(self.faces.len() + 1);
        let mut above = Vec::with_capacity(self.faces.len() + 1);
        let mut cap: Vec<DVec3> = Vec::new();
        for (face, values) in self.faces.iter().zip(&values) {
            let n = face.corners.len();
            let mut low = Vec::with_capacity(n + 1);
            let mut high = Vec::with_capacity(n + 1);
            for i in 0..n {
                let (v, w) = (face.corners[i], face.corners[(i + 1) % n]);
                let (dv, dw) = (values[i], values[(i + 1) % n]);
                if dv <= tolerance {
                    low.push(v);
                }
                if dv >= -tolerance {
                    high.push(v);
                }
                if dv.abs() <= tolerance {
                    cap.push(v);
                }
                if (dv < -tolerance && dw > tolerance) || (dv > tolerance && dw < -tolerance) {
                    let x = crossing(v, w, dv, dw);
                    low.push(x);
                    high.push(x);
                    cap.push(x);
                }
            }
            if low.len() >= 3 {
                below.push(Face {
                    plane: face.plane,
                    corners: low,
                });
            }
            if high.len() >= 3 {
                above.push(Face {
                    plane: face.plane,
                    corners: high,
                });
            }
        }
        let cap = order_around(cap, plane.normal);
        if cap.len() >= 3 {
            below.push(Face {
                plane,
                corners: cap.clone(),
            });
            above.push(Face {
                plane: plane.flipped(),
                corners: cap,
            });
        }
        Some((Polytope { faces: below }, Polytope { faces: above }))
    }

    /// The polytope as a cell whose box is the corners' padded by `pad`, within `[min, max]`.
    pub(super) fn into_cell(self, pad: f64, min: DVec3, max: DVec3) -> Cell3 {
        let (lo, hi) = self.bounds();
        Cell3 {
            planes: self.faces.into_iter().map(|f| f.plane).collect(),
            min: (lo - pad).max(min),
            max: (hi + pad).min(max),
        }
    }
}

/// The distinct points of a planar convex polygon, in cyclic order around their mean.
fn order_around(mut points: Vec<DVec3>, normal: DVec3) -> Vec<DVec3> {
    points.sort_by(|a, b| {
        (a.x, a.y, a.z)
            .partial_cmp(&(b.x, b.y, b.z))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let centre = points.iter().sum::<DVec3>() / points.len() as f64;
    let unit = normal.normalize_or(DVec3::Z);
    let u = unit.any_orthonormal_vector();
    let v = unit.cross(u);
    let angle = |p: &DVec3| {
        let d = *p - centre;
        d.dot(v).atan2(d.dot(u))
    };
    points.sort_by(|a, b| angle(a).total_cmp(&angle(b)));
    points
}
