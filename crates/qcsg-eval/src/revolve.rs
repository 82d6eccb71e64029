//! `rotate_extrude` as exact quadric solids: the 2-D shape in the (x, y) plane is read as
//! (r, z) with r = x ≥ 0, and a point p is in the solid when (√(px² + py²), pz) is in the shape.
//!
//! That map is a preimage, so it commutes with union, intersection, difference and complement:
//! the solid is the shape's boolean expression ([`crate::planar`]) with each conic leaf replaced
//! by its own solid of revolution ([`revolve_conic`]):
//!
//! | conic in (r, z) | solid |
//! | --- | --- |
//! | `b z ≤ c` (no r) | the plane `b z ≤ c` |
//! | `a r + b z ≤ c`, `a > 0` | `r ≤ (c − b z)/a`: the cone `a² r² ≤ (c − b z)²` ∩ the half-space `b z ≤ c` (a cylinder if `b = 0`) |
//! | `a r + b z ≤ c`, `a < 0` | `r ≥ (b z − c)/|a|`: the half-space `b z ≤ c` ∪ the outside of the cone (of the cylinder if `b = 0`) |
//! | a strip between parallel lines | its two half-planes, each as above |
//! | no odd power of r (a circle or ellipse centred on the axis) | the quadric with r² = x² + y² (a sphere, an ellipsoid of revolution) |
//! | odd powers of r (a circle off the axis) | a torus or another quartic: refused |
//!
//! A shape wholly at x ≤ 0 is mirrored to x ≥ 0 first, as OpenSCAD 2021.01 sweeps it; a partial
//! `angle` intersects the result with a wedge of half-spaces ([`wedge`]).

use glam::{DMat3, DVec2, DVec3};
use qcsg_csg::{Aabb, Dag, Edge, Source};
use qcsg_quadric::Quadric;

use crate::planar::Conic;

/// Relative tolerance for the terms in odd powers of r that rounding leaves on a conic centred on
/// the axis (a circle rotated about the origin, say).
const ON_AXIS_TOLERANCE: f64 = 1e-9;

/// Why a conic has no solid of revolution bounded by one quadric: its curve is off the axis, so
/// it sweeps a torus (a circle) or another quartic surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OffAxis;

/// The mirror image x → −x, to sweep a shape lying at x ≤ 0.
pub fn mirror_x() -> DMat3 {
    DMat3::from_diagonal(DVec3::new(-1.0, 1.0, 1.0))
}

fn quadric(origin_z: f64, coefficients: [f64; 10]) -> Option<Quadric> {
    Quadric::new(DVec3::new(0.0, 0.0, origin_z), coefficients)
}

fn leaf(dag: &mut Dag, q: Option<Quadric>, source: Source) -> Edge {
    match q {
        Some(q) => dag.leaf(q, source).into(),
        None => dag.empty(source).into(),
    }
}

fn everything(dag: &mut Dag, source: Source) -> Edge {
    let none = dag.empty(source);
    dag.complement(none.into(), source).into()
}

/// The solid swept by the half-plane `a r + b Z ≤ c` (Z = z − `origin_z`).
fn revolve_half_plane(
    dag: &mut Dag,
    (a, b, c): (f64, f64, f64),
    origin_z: f64,
    source: Source,
) -> Edge {
    // The half-space b Z ≤ c, written about the cone's apex Z = c/b when there is one.
    let below = |b: f64| {
        [
            0.0,
            0.0,
            0.0,
            0.0,
            0.0,
            0.0,
            0.0,
            0.0,
            0.5 * b.signum(),
            0.0,
        ]
    };
    if a == 0.0 {
        if b == 0.0 {
            return if c >= 0.0 {
                everything(dag, source)
            } else {
                dag.empty(source).into()
            };
        }
        return leaf(dag, quadric(origin_z + c / b, below(b)), source);
    }
    if b == 0.0 {
        // r ≤ c/a (a > 0) or r ≥ c/a (a < 0): a cylinder about the axis or its outside.
        let radius = c / a;
        return match (a > 0.0, radius > 0.0) {
            (true, true) => leaf(
                dag,
                Quadric::cylinder(DVec3::ZERO, DVec3::Z, radius),
                source,
            ),
            (true, false) => dag.empty(source).into(),
            (false, true) => {
                let outside = [
                    -1.0,
                    -1.0,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                    radius * radius,
                ];
                leaf(dag, quadric(0.0, outside), source)
            }
            (false, false) => everything(dag, source),
        };
    }
    // About the apex W = Z − c/b: c − b Z = −b W, so a² r² ≤ (c − b Z)² is r² − (b/a)² W² ≤ 0.
    let apex = origin_z + c / b;
    let slope = (b / a) * (b / a);
    let half_space = leaf(dag, quadric(apex, below(b)), source);
    if a > 0.0 {
        let cone = [1.0, 1.0, -slope, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        let cone = leaf(dag, quadric(apex, cone), source);
        dag.intersection([cone, half_space], source).into()
    } else {
        let outside = [-1.0, -1.0, slope, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        let outside = leaf(dag, quadric(apex, outside), source);
        dag.union([half_space, outside], source).into()
    }
}

/// The half-plane `[0, 0, 0, g, h, j]` of `conic` as `a r + b Z ≤ c` about Z = z − origin.y.
fn half_plane_terms(conic: &Conic) -> (f64, f64, f64) {
    let [_, _, _, g, h, j] = conic.coefficients();
    // 2g (r − ox) + 2h Z + j ≤ 0.
    (2.0 * g, 2.0 * h, -(j - 2.0 * g * conic.origin.x))
}

/// The solid swept about the z axis by the figure of `conic` read in (r, z), r ≥ 0.
pub fn revolve_conic(dag: &mut Dag, conic: &Conic, source: Source) -> Result<Edge, OffAxis> {
    let origin_z = conic.origin.y;
    if conic.is_linear() {
        return Ok(revolve_half_plane(
            dag,
            half_plane_terms(conic),
            origin_z,
            source,
        ));
    }
    if let Some([first, second]) = conic.split_strip() {
        let first = revolve_half_plane(dag, half_plane_terms(&first), origin_z, source);
        let second = revolve_half_plane(dag, half_plane_terms(&second), origin_z, source);
        return Ok(dag.intersection([first, second], source).into());
    }
    let [a, b, d, g, h, j] = conic.coefficients();
    let ox = conic.origin.x;
    // a (r − ox)² + 2g (r − ox) = a r² + 2 (g − a ox) r + a ox² − 2g ox; 2d (r − ox) Z has r Z.
    let odd = g - a * ox;
    let scale = a.abs() + b.abs();
    let size = (j.abs() / scale).sqrt() + ox.abs() + (g / a).abs();
    if d.abs() > ON_AXIS_TOLERANCE * scale
        || a == 0.0
        || odd.abs() > ON_AXIS_TOLERANCE * a.abs() * size
    {
        return Err(OffAxis);
    }
    let constant = j + a * ox * ox - 2.0 * g * ox;
    let q = quadric(origin_z, [a, a, b, 0.0, 0.0, 0.0, 0.0, 0.0, h, constant]);
    Ok(leaf(dag, q, source))
}

/// The wedge of the directions at angles from `start` to `start + sweep` degrees
/// (counter-clockwise about +z, 0 < sweep < 360), unbounded in z: two half-spaces through the
/// axis, intersected for a sweep up to 180° and united beyond.
pub fn wedge(dag: &mut Dag, start: f64, sweep: f64, source: Source) -> Edge {
    let direction = |degrees: f64| {
        DVec2::new(
            crate::math::cos_degrees(degrees),
            crate::math::sin_degrees(degrees),
        )
    };
    let (from, to) = (direction(start), direction(start + sweep));
    // Counter-clockwise of `from`: from × p ≥ 0, i.e. (from.y, −from.x) · p ≤ 0.
    let after = Quadric::half_space(DVec3::ZERO, DVec3::new(from.y, -from.x, 0.0));
    // Clockwise of `to`: to × p ≤ 0, i.e. (−to.y, to.x) · p ≤ 0.
    let before = Quadric::half_space(DVec3::ZERO, DVec3::new(-to.y, to.x, 0.0));
    let (after, before) = (leaf(dag, after, source), leaf(dag, before, source));
    if sweep <= 180.0 {
        dag.intersection([after, before], source).into()
    } else {
        dag.union([after, before], source).into()
    }
}

/// The box of the solid swept by a shape whose (r, z) box is `[min, max]`.
pub fn swept_box(min: DVec2, max: DVec2) -> Aabb {
    let radius = min.x.abs().max(max.x.abs());
    Aabb::new(
        DVec3::new(-radius, -radius, min.y),
        DVec3::new(radius, radius, max.y),
    )
}
