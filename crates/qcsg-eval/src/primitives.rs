//! Built-in primitives lowered to the fewest exact quadrics, with OpenSCAD's placement.
//!
//! | primitive | quadrics | placement |
//! | --- | --- | --- |
//! | `cube(size, center)` | 3 slabs `(x − c)² ≤ a²` | `[0, size]` per axis unless centred |
//! | `sphere(r \| d)` | 1 ellipsoid | centred at the origin |
//! | `cylinder(h, r1, r2, center, r, d, d1, d2)` | infinite cylinder or cone ∩ 1 z-slab | `z ∈ [0, h]` unless centred |
//! | `ellipsoid(r \| d)`, `r` a number or `[a, b, c]` | 1 ellipsoid | centred at the origin |
//! | `paraboloid(h = 1, r = 1, center)` | paraboloid ∩ 1 half-space | apex at `z = 0`, radius `r` at `z = h` |
//! | `cone(h = 1, r = 1, center)` | cone ∩ 1 z-slab | apex at `z = 0`, radius `r` at `z = h` |
//! | `hyperboloid(h = 1, r = 1, c = 1, sheets = 1, center)` | hyperboloid ∩ 1 z-slab | symmetric about `z = h/2` (about 0 if centred) |
//! | `halfspace(normal, offset = 0)` | 1 half-space `normal · p ≤ offset` | unbounded |
//! | `quadric(q)` | the quadric, `q` a symmetric 4×4 matrix or 10 coefficients | unbounded |
//!
//! `r` of `paraboloid`, `cone` and `hyperboloid` may be `[rx, ry]` (elliptic sections). The
//! hyperboloid of one sheet is `x²/rx² + y²/ry² − z²/c² ≤ 1` (waist radius `r`), of two sheets
//! `z²/c² − x²/rx² − y²/ry² ≥ 1` (vertices at `±c`), both about their centre and cut to a height
//! `h`. As in OpenSCAD, `center` counts only when it is a boolean, and zero or negative sizes
//! make an empty solid (with a warning), not an error. Every quadric is expressed about its
//! primitive's centre so its coefficients stay well-conditioned, and every finite primitive
//! declares its box.

use glam::DVec3;
use qcsg_csg::{Aabb, Dag, NodeId, Source};
use qcsg_quadric::Quadric;

use crate::value::Value;

/// The named arguments of a built-in module call, after positional ones were placed.
pub trait ArgLookup<'a> {
    /// The value of parameter `name` (`Undef` when absent).
    fn get(&self, name: &str) -> Value<'a>;
}

/// What building a primitive produced.
pub enum Built {
    /// The primitive's node.
    Node(NodeId),
    /// An empty solid (zero or negative size), with the reason.
    Empty(String),
}

/// A primitive's arguments are unusable: the message.
pub type BuildResult = Result<Built, String>;

fn center_of(args: &dyn ArgLookup<'_>) -> bool {
    matches!(args.get("center"), Value::Bool(true))
}

fn number(args: &dyn ArgLookup<'_>, name: &str, default: f64) -> Result<f64, String> {
    match args.get(name) {
        Value::Undef => Ok(default),
        Value::Number(x) => Ok(x),
        other => Err(format!(
            "`{name}` must be a number, got {}",
            other.type_name()
        )),
    }
}

/// `r`, or half of `d` when given (which OpenSCAD prefers).
fn radius(args: &dyn ArgLookup<'_>, d: &str, r: &str) -> Result<Option<f64>, String> {
    match (args.get(d), args.get(r)) {
        (Value::Number(d), _) => Ok(Some(d / 2.0)),
        (Value::Undef, Value::Number(r)) => Ok(Some(r)),
        (Value::Undef, Value::Undef) => Ok(None),
        (Value::Undef, other) | (other, _) => Err(format!(
            "a radius or diameter must be a number, got {}",
            other.type_name()
        )),
    }
}

/// A number or `[x, y]` as two radii.
fn radii2(args: &dyn ArgLookup<'_>, name: &str) -> Result<(f64, f64), String> {
    match args.get(name) {
        Value::Undef => Ok((1.0, 1.0)),
        Value::Number(r) => Ok((r, r)),
        other => other
            .as_numbers(2)
            .map(|v| (v[0], v[1]))
            .ok_or_else(|| format!("`{name}` must be a number or [rx, ry]")),
    }
}

fn positive(x: f64) -> bool {
    x > 0.0 && x.is_finite()
}

fn leaf(dag: &mut Dag, q: Option<Quadric>, source: Source, bounds: Aabb) -> Result<NodeId, String> {
    let q = q.ok_or("the primitive's size is not representable")?;
    Ok(dag.bounded_leaf(q, source, bounds))
}

fn z_slab_bounds(centre: DVec3, half: f64) -> Aabb {
    Aabb::new(
        DVec3::new(f64::NEG_INFINITY, f64::NEG_INFINITY, centre.z - half),
        DVec3::new(f64::INFINITY, f64::INFINITY, centre.z + half),
    )
}

/// Builds the primitive `name` (one of the table above, `complement` excluded).
pub fn build(dag: &mut Dag, name: &str, args: &dyn ArgLookup<'_>, source: Source) -> BuildResult {
    match name {
        "cube" => cube(dag, args, source),
        "sphere" => {
            let r = radius(args, "d", "r")?.unwrap_or(1.0);
            if !positive(r) {
                return Ok(Built::Empty(format!("sphere with radius {r} is empty")));
            }
            let q = Quadric::sphere(DVec3::ZERO, r);
            let b = Aabb::from_centre_half(DVec3::ZERO, DVec3::splat(r));
            Ok(Built::Node(leaf(dag, q, source, b)?))
        }
        "ellipsoid" => {
            let r = match (args.get("d"), args.get("r")) {
                (Value::Undef, Value::Undef) => [1.0; 3],
                (Value::Undef, v) => vec3_or_number(&v, "r")?,
                (v, _) => vec3_or_number(&v, "d")?.map(|d| d / 2.0),
            };
            if !r.iter().all(|&x| positive(x)) {
                return Ok(Built::Empty(
                    "ellipsoid with a non-positive radius is empty".into(),
                ));
            }
            let radii = DVec3::from_array(r);
            let q = Quadric::ellipsoid(DVec3::ZERO, radii);
            let b = Aabb::from_centre_half(DVec3::ZERO, radii);
            Ok(Built::Node(leaf(dag, q, source, b)?))
        }
        "cylinder" => cylinder(dag, args, source),
        "paraboloid" | "cone" | "hyperboloid" => native_z(dag, name, args, source),
        "halfspace" => {
            let normal = args
                .get("normal")
                .as_numbers(3)
                .ok_or("halfspace(normal) needs a normal of 3 numbers")?;
            let offset = number(args, "offset", 0.0)?;
            let n = DVec3::new(normal[0], normal[1], normal[2]);
            let len2 = n.length_squared();
            if len2 == 0.0 || !len2.is_finite() {
                return Err("halfspace(normal) needs a non-zero normal".into());
            }
            let q = Quadric::half_space(n * (offset / len2), n)
                .ok_or("halfspace(normal, offset) is not representable")?;
            Ok(Built::Node(dag.leaf(q, source)))
        }
        "quadric" => {
            let q = args.get("q");
            let k = quadric_coefficients(&q)?;
            let q = Quadric::new(DVec3::ZERO, k).ok_or("quadric(q) needs finite coefficients")?;
            Ok(Built::Node(dag.leaf(q, source)))
        }
        other => Err(format!("`{other}` is not a primitive")),
    }
}

fn vec3_or_number(v: &Value<'_>, name: &str) -> Result<[f64; 3], String> {
    match v {
        Value::Number(x) => Ok([*x; 3]),
        other => other
            .as_numbers(3)
            .map(|v| [v[0], v[1], v[2]])
            .ok_or_else(|| format!("`{name}` must be a number or a vector of 3 numbers")),
    }
}

/// `[a, b, c, d, e, f, g, h, i, j]` from 10 coefficients or a (symmetrised) 4×4 matrix.
fn quadric_coefficients(q: &Value<'_>) -> Result<[f64; 10], String> {
    if let Some(k) = q.as_numbers(10) {
        let mut out = [0.0; 10];
        out.copy_from_slice(&k);
        return Ok(out);
    }
    let rows = q
        .as_vector()
        .filter(|r| r.len() == 4)
        .and_then(|r| {
            r.iter()
                .map(|row| row.as_numbers(4))
                .collect::<Option<Vec<_>>>()
        })
        .ok_or("quadric(q) needs a 4x4 matrix or 10 coefficients")?;
    let s = |i: usize, j: usize| 0.5 * (rows[i][j] + rows[j][i]);
    Ok([
        rows[0][0],
        rows[1][1],
        rows[2][2],
        s(0, 1),
        s(0, 2),
        s(1, 2),
        s(0, 3),
        s(1, 3),
        s(2, 3),
        rows[3][3],
    ])
}

fn cube(dag: &mut Dag, args: &dyn ArgLookup<'_>, source: Source) -> BuildResult {
    let size = match args.get("size") {
        Value::Undef => [1.0; 3],
        Value::Number(s) => [s; 3],
        other => other
            .as_vec3(0.0)
            .ok_or("cube(size) needs a number or a vector of 3 numbers")?,
    };
    if !size.iter().all(|&s| positive(s)) {
        return Ok(Built::Empty(format!(
            "cube with size [{}, {}, {}] is empty",
            size[0], size[1], size[2]
        )));
    }
    let half = DVec3::from_array(size) / 2.0;
    let centre = if center_of(args) { DVec3::ZERO } else { half };
    let mut slabs = Vec::with_capacity(3);
    for (axis, dir) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().enumerate() {
        let h = half[axis];
        let mut lo = DVec3::NEG_INFINITY;
        let mut hi = DVec3::INFINITY;
        lo[axis] = centre[axis] - h;
        hi[axis] = centre[axis] + h;
        let q = Quadric::slab(centre, dir, h);
        slabs.push(leaf(dag, q, source, Aabb::new(lo, hi))?.into());
    }
    let node = dag.intersection(slabs, source);
    Ok(Built::Node(
        dag.bounded(node, Aabb::from_centre_half(centre, half)),
    ))
}

fn cylinder(dag: &mut Dag, args: &dyn ArgLookup<'_>, source: Source) -> BuildResult {
    let h = number(args, "h", 1.0)?;
    let r = radius(args, "d", "r")?;
    let r1 = radius(args, "d1", "r1")?;
    let r2 = radius(args, "d2", "r2")?;
    let (mut bottom, mut top) = (1.0, 1.0);
    if let Some(r) = r {
        bottom = r;
        top = r;
    }
    if let Some(r1) = r1 {
        bottom = r1;
    }
    if let Some(r2) = r2 {
        top = r2;
    }
    if !(positive(h) && bottom >= 0.0 && top >= 0.0 && (bottom > 0.0 || top > 0.0))
        || !bottom.is_finite()
        || !top.is_finite()
    {
        return Ok(Built::Empty(format!(
            "cylinder with h = {h}, r1 = {bottom}, r2 = {top} is empty"
        )));
    }
    let zc = if center_of(args) { 0.0 } else { h / 2.0 };
    let centre = DVec3::new(0.0, 0.0, zc);
    let rmax = bottom.max(top);
    let lateral = if bottom == top {
        Quadric::cylinder(centre, DVec3::Z, bottom)
    } else {
        // x² + y² ≤ (r_mid + k z)², z about the centre: a double cone whose far nappe lies
        // beyond the apex, outside the slab.
        let k = (top - bottom) / h;
        let r_mid = (bottom + top) / 2.0;
        Quadric::new(
            centre,
            [
                1.0,
                1.0,
                -k * k,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                -k * r_mid,
                -r_mid * r_mid,
            ],
        )
    };
    let lateral = lateral.ok_or("the primitive's size is not representable")?;
    let side = if bottom == top {
        let side_bounds = Aabb::new(
            DVec3::new(-rmax, -rmax, f64::NEG_INFINITY),
            DVec3::new(rmax, rmax, f64::INFINITY),
        );
        dag.bounded_leaf(lateral, source, side_bounds)
    } else {
        dag.leaf(lateral, source)
    };
    let slab = leaf(
        dag,
        Quadric::slab(centre, DVec3::Z, h / 2.0),
        source,
        z_slab_bounds(centre, h / 2.0),
    )?;
    let node = dag.intersection([side.into(), slab.into()], source);
    let b = Aabb::from_centre_half(centre, DVec3::new(rmax, rmax, h / 2.0));
    Ok(Built::Node(dag.bounded(node, b)))
}

fn native_z(dag: &mut Dag, name: &str, args: &dyn ArgLookup<'_>, source: Source) -> BuildResult {
    let h = number(args, "h", 1.0)?;
    let (rx, ry) = radii2(args, "r")?;
    if !(positive(h) && positive(rx) && positive(ry)) {
        return Ok(Built::Empty(format!(
            "{name} with a non-positive size is empty"
        )));
    }
    let zc = if center_of(args) { 0.0 } else { h / 2.0 };
    let centre = DVec3::new(0.0, 0.0, zc);
    let (wx, wy) = (1.0 / (rx * rx), 1.0 / (ry * ry));
    let slab_bounds = z_slab_bounds(centre, h / 2.0);
    let (surface, cap_scale, cut, cut_bounds) = match name {
        "paraboloid" => {
            // x²/rx² + y²/ry² ≤ (z_local + h/2) / h; the surface itself closes the bottom.
            let q = Quadric::new(
                centre,
                [wx, wy, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.5 / h, -0.5],
            );
            let top = Quadric::half_space(DVec3::new(0.0, 0.0, zc + h / 2.0), DVec3::Z);
            let below = Aabb::new(
                DVec3::NEG_INFINITY,
                DVec3::new(f64::INFINITY, f64::INFINITY, zc + h / 2.0),
            );
            (q, 1.0, top, below)
        }
        "cone" => {
            // x²/rx² + y²/ry² ≤ ((z_local + h/2) / h)², the upper nappe cut by the slab.
            let q = Quadric::new(
                centre,
                [
                    wx,
                    wy,
                    -1.0 / (h * h),
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                    -0.5 / h,
                    -0.25,
                ],
            );
            (
                q,
                1.0,
                Quadric::slab(centre, DVec3::Z, h / 2.0),
                slab_bounds,
            )
        }
        _ => {
            let c = number(args, "c", 1.0)?;
            let sheets = number(args, "sheets", 1.0)?;
            if !positive(c) {
                return Err(format!("hyperboloid needs c > 0, got {c}"));
            }
            let t = (h / 2.0) / c;
            let (j, cap) = if sheets == 1.0 {
                (-1.0, (1.0 + t * t).sqrt())
            } else if sheets == 2.0 {
                if t <= 1.0 {
                    return Ok(Built::Empty(format!(
                        "hyperboloid of two sheets with h/2 = {} <= c = {c} is empty",
                        h / 2.0
                    )));
                }
                (1.0, (t * t - 1.0).sqrt())
            } else {
                return Err(format!("hyperboloid(sheets) must be 1 or 2, got {sheets}"));
            };
            let q = Quadric::new(
                centre,
                [wx, wy, -1.0 / (c * c), 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, j],
            );
            (
                q,
                cap,
                Quadric::slab(centre, DVec3::Z, h / 2.0),
                slab_bounds,
            )
        }
    };
    let half = DVec3::new(rx * cap_scale, ry * cap_scale, h / 2.0);
    // The surface alone is unbounded; the intersection with the cut declares the box.
    let surface = surface.ok_or("the primitive's size is not representable")?;
    let side = dag.leaf(surface, source);
    let cut = cut.ok_or("the primitive's size is not representable")?;
    let cut = dag.bounded_leaf(cut, source, cut_bounds);
    let node = dag.intersection([side.into(), cut.into()], source);
    Ok(Built::Node(
        dag.bounded(node, Aabb::from_centre_half(centre, half)),
    ))
}
