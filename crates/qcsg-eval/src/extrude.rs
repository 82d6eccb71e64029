//! `linear_extrude`: a 2-D shape (a z-invariant solid) cut by a slab, exactly.
//!
//! Without `scale` the extrusion is the shape ∩ the slab `0 ≤ z ≤ h` (`−h/2 ≤ z ≤ h/2` when
//! centred), built directly on the shape's DAG. With `scale = s` the section at height `z` is the
//! shape scaled about the z axis by `t = 1 + (s − 1)(z − z₀)/h`. That map is not projective, but
//! substituting `x = x'/t`, `y = y'/t` into a conic leaf and multiplying by `t²` (positive inside
//! the slab) gives a quadric in `(x', y', z)`: a circle becomes a cone, a strip a wedge, and a
//! half-plane, multiplied by `t` only, stays a plane. With `scale = [sx, sy]`, `sx ≠ sy`, a
//! half-plane multiplied by `tx·ty` is still a quadric, and so is a strip across x or y
//! multiplied by `tx²` or `ty²` (other strips are split into their two half-planes), but a
//! circle or ellipse would need degree 4: [`ScaleError`] names it. `scale = 0` brings the shape
//! to a point at the top. `twist` makes helicoids, which are no quadrics; the evaluator rejects
//! it before anything is built.

use glam::{DVec2, DVec3, DVec4};
use qcsg_csg::{Aabb, Dag, Edge, Source};
use qcsg_quadric::Quadric;

use crate::planar::{Conic, PlanarExpr, rebuild};
use crate::primitives::ArgLookup;
use crate::value::Value;

/// The arguments of `linear_extrude` that shape the solid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearExtrude {
    /// The height (OpenSCAD's default 100).
    pub height: f64,
    /// Whether the slab is centred on z = 0.
    pub center: bool,
    /// The scale of the top section (negative entries are 0, as in OpenSCAD).
    pub scale: DVec2,
    /// The twist in degrees.
    pub twist: f64,
}

impl LinearExtrude {
    /// The z range `[bottom, top]` of the slab.
    pub fn z_range(&self) -> (f64, f64) {
        if self.center {
            (-self.height / 2.0, self.height / 2.0)
        } else {
            (0.0, self.height)
        }
    }
}

/// Reads the arguments of `linear_extrude(height = 100, center = false, convexity, twist = 0,
/// slices, scale = 1)`: `Err((parameter, message))` for an unusable one. As in OpenSCAD a
/// `center` that is not a boolean counts as false; `convexity`, `slices` and `segments` change
/// nothing on an exact solid.
pub fn linear_extrude_args(
    args: &dyn ArgLookup<'_>,
) -> Result<LinearExtrude, (&'static str, String)> {
    let height = match args.get("height") {
        Value::Undef => 100.0,
        Value::Number(h) => h,
        other => {
            return Err((
                "height",
                format!(
                    "linear_extrude(height) needs a number, got {}",
                    other.type_name()
                ),
            ));
        }
    };
    let scale = match args.get("scale") {
        Value::Undef => DVec2::ONE,
        Value::Number(s) => DVec2::splat(s),
        other => other.as_numbers(2).map(|v| DVec2::new(v[0], v[1])).ok_or((
            "scale",
            "linear_extrude(scale) needs a number or a vector of 2 numbers".to_string(),
        ))?,
    };
    if !scale.is_finite() {
        return Err(("scale", "linear_extrude(scale) must be finite".into()));
    }
    let twist = match args.get("twist") {
        Value::Undef => 0.0,
        Value::Number(t) => t,
        other => {
            return Err((
                "twist",
                format!(
                    "linear_extrude(twist) needs a number, got {}",
                    other.type_name()
                ),
            ));
        }
    };
    Ok(LinearExtrude {
        height,
        center: matches!(args.get("center"), Value::Bool(true)),
        scale: scale.max(DVec2::ZERO),
        twist,
    })
}

/// A conic leaf that a non-uniform `scale` would turn into a surface of degree 4.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ScaleError {
    /// The code that made the curved leaf.
    pub curved: Source,
}

/// The affine forms of one extrusion over the local coordinates `(X', Y', Z', 1)` of a leaf's
/// quadric: `u_x = x' − o_x t_x`, `u_y`, and the scale factors `t_x`, `t_y` at each height.
struct Forms {
    ux: DVec4,
    uy: DVec4,
    tx: DVec4,
    ty: DVec4,
    origin: DVec3,
}

/// The symmetric 4×4 form `Σ c · f g` as a quadric's ten coefficients.
fn quadric_of(origin: DVec3, products: &[(f64, DVec4, DVec4)]) -> Option<Quadric> {
    let mut s = [[0.0; 4]; 4];
    for (c, f, g) in products {
        for (i, row) in s.iter_mut().enumerate() {
            for (j, e) in row.iter_mut().enumerate() {
                *e += 0.5 * c * (f[i] * g[j] + g[i] * f[j]);
            }
        }
    }
    let k = [
        s[0][0], s[1][1], s[2][2], s[0][1], s[0][2], s[1][2], s[0][3], s[1][3], s[2][3], s[3][3],
    ];
    k.iter().all(|x| x.is_finite()).then_some(())?;
    Quadric::new(origin, k)
}

/// The solid swept by `expr`'s shape between `bottom` and `top` while it is scaled from 1 at
/// the bottom to `scale` at the top, about the z axis. `source` is the call's; `shape_box`, a
/// box of the plane containing the shape, bounds the result.
pub fn scaled_extrusion(
    dag: &mut Dag,
    expr: &PlanarExpr,
    shape_box: Option<(DVec2, DVec2)>,
    bottom: f64,
    top: f64,
    scale: DVec2,
    source: Source,
) -> Result<Edge, ScaleError> {
    let height = top - bottom;
    let k = (scale - DVec2::ONE) / height;
    let z_mid = 0.5 * (bottom + top);
    let t_mid = DVec2::ONE + k * (z_mid - bottom);
    let uniform = scale.x == scale.y;
    let forms = |o: DVec2| Forms {
        ux: DVec4::new(1.0, 0.0, -o.x * k.x, 0.0),
        uy: DVec4::new(0.0, 1.0, -o.y * k.y, 0.0),
        tx: DVec4::new(0.0, 0.0, k.x, t_mid.x),
        ty: DVec4::new(0.0, 0.0, k.y, t_mid.y),
        origin: DVec3::new(o.x * t_mid.x, o.y * t_mid.y, z_mid),
    };
    let one = DVec4::W;
    let leaf_quadric = |conic: &Conic| -> Option<Quadric> {
        let [a, b, d, g, h, j] = conic.coefficients();
        let f = forms(conic.origin);
        if conic.is_linear() {
            // Multiplied by t (uniform) or tx·ty: a plane, or a quadric.
            return if uniform {
                quadric_of(
                    f.origin,
                    &[(2.0 * g, f.ux, one), (2.0 * h, f.uy, one), (j, f.tx, one)],
                )
            } else {
                quadric_of(
                    f.origin,
                    &[
                        (2.0 * g, f.ux, f.ty),
                        (2.0 * h, f.uy, f.tx),
                        (j, f.tx, f.ty),
                    ],
                )
            };
        }
        if uniform {
            let t = f.tx;
            return quadric_of(
                f.origin,
                &[
                    (a, f.ux, f.ux),
                    (b, f.uy, f.uy),
                    (2.0 * d, f.ux, f.uy),
                    (2.0 * g, f.ux, t),
                    (2.0 * h, f.uy, t),
                    (j, t, t),
                ],
            );
        }
        if b == 0.0 && d == 0.0 && h == 0.0 {
            return quadric_of(
                f.origin,
                &[(a, f.ux, f.ux), (2.0 * g, f.ux, f.tx), (j, f.tx, f.tx)],
            );
        }
        if a == 0.0 && d == 0.0 && g == 0.0 {
            return quadric_of(
                f.origin,
                &[(b, f.uy, f.uy), (2.0 * h, f.uy, f.ty), (j, f.ty, f.ty)],
            );
        }
        None
    };
    let low = scale.min(DVec2::ONE);
    let high = scale.max(DVec2::ONE);
    let boxed = |min: DVec2, max: DVec2| {
        // Sections scale about the axis by factors between 1 and `scale`: the box of both
        // ends contains every section.
        let lo = (min * low).min(min * high);
        let hi = (max * low).max(max * high);
        Aabb::new(lo.extend(bottom), hi.extend(top))
    };
    let swept = rebuild(
        dag,
        expr,
        |dag: &mut Dag, conic: &Conic, at: Source| -> Result<Edge, ScaleError> {
            if let Some(q) = leaf_quadric(conic) {
                return Ok(dag.leaf(q, at).into());
            }
            let curved = ScaleError { curved: at };
            let halves = conic.split_strip().ok_or(curved)?;
            let mut parts = Vec::with_capacity(2);
            for half in &halves {
                let q = leaf_quadric(half).ok_or(curved)?;
                parts.push(dag.leaf(q, at).into());
            }
            Ok(dag.intersection(parts, at).into())
        },
        boxed,
    )?;
    let half = 0.5 * height;
    let slab_box = Aabb::new(
        DVec3::new(f64::NEG_INFINITY, f64::NEG_INFINITY, bottom),
        DVec3::new(f64::INFINITY, f64::INFINITY, top),
    );
    let Some(slab) = Quadric::slab(DVec3::new(0.0, 0.0, z_mid), DVec3::Z, half) else {
        return Ok(dag.empty(source).into());
    };
    let slab = dag.bounded_leaf(slab, source, slab_box);
    let cut = dag.intersection([swept, slab.into()], source);
    let cut = match shape_box {
        Some((min, max)) => dag.bounded(cut, boxed(min, max)),
        None => cut,
    };
    Ok(cut.into())
}
