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

    /// Whether the triangle may reach into the polytope's interior: the triangle clipped by
    /// every face plane, each moved inwards by its tolerance, leaves something.
    ///
    /// A triangle that meets the polytope only on its boundary (a fan's triangle at the vertex
    /// the fan shares with the region, a neighbour along a wall) cannot change the parity inside
    /// it, so it is left out: keeping every triangle through a vertex of the region made the
    /// regions around a fan's centre multiply with the square of the fan, each holding all of
    /// it. Within the tolerance the decision is the same one [`Polytope::split`] makes for a
    /// plane that grazes a region: what it leaves out lies within rounding of the surface.
    pub(super) fn may_touch(
        &self,
        triangle: [DVec3; 3],
        tolerance: impl Fn(&Plane) -> f64,
    ) -> bool {
        // Clipping by a half-space adds at most one corner: buffers on the stack suffice for
        // all but the rare region of many faces, and this runs for every triangle of every
        // region twice.
        const ON_STACK: usize = 32;
        let capacity = self.faces.len() + 3;
        if capacity <= ON_STACK {
            let mut a = [DVec3::ZERO; ON_STACK];
            let mut b = [DVec3::ZERO; ON_STACK];
            self.clip_leaves_something(triangle, &tolerance, &mut a, &mut b)
        } else {
            let mut a = vec![DVec3::ZERO; capacity];
            let mut b = vec![DVec3::ZERO; capacity];
            self.clip_leaves_something(triangle, &tolerance, &mut a, &mut b)
        }
    }

    /// [`Polytope::may_touch`] with two buffers of at least `faces + 3` points.
    fn clip_leaves_something<'b>(
        &self,
        triangle: [DVec3; 3],
        tolerance: &impl Fn(&Plane) -> f64,
        mut polygon: &'b mut [DVec3],
        mut next: &'b mut [DVec3],
    ) -> bool {
        polygon[..3].copy_from_slice(&triangle);
        let mut n = 3;
        // Newest face first: the parent's triangles all reach past the older ones, and a split's
        // cap is the face last added.
        for face in self.faces.iter().rev() {
            let slack = tolerance(&face.plane);
            let value = |v: DVec3| face.plane.value(v) + slack;
            let outside = polygon[..n].iter().filter(|&&v| value(v) > 0.0).count();
            if outside == 0 {
                continue;
            }
            if outside == n {
                return false;
            }
            let mut m = 0;
            for i in 0..n {
                let (v, w) = (polygon[i], polygon[(i + 1) % n]);
                let (dv, dw) = (value(v), value(w));
                if dv <= 0.0 {
                    next[m] = v;
                    m += 1;
                }
                if (dv <= 0.0) != (dw <= 0.0) {
                    next[m] = v + (w - v) * (dv / (dv - dw));
                    m += 1;
                }
            }
            std::mem::swap(&mut polygon, &mut next);
            n = m;
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
