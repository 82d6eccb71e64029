//! OpenSCAD's 2-D primitives as z-invariant solids (see [`crate::planar`]).
//!
//! | primitive | quadrics | placement |
//! | --- | --- | --- |
//! | `square(size, center)` | 2 slabs `(x − c)² ≤ a²` with normals along x and y | `[0, size]` per axis unless centred |
//! | `circle(r \| d)` | 1 cylinder along z | centred at the origin |
//! | `polygon(points, paths)` | a union of convex cells, each an intersection of half-spaces | the points as given |
//!
//! As for spheres, `circle` is exact and `$fn`, `$fa`, `$fs` change nothing. Every node declares
//! its box, bounded in x and y and unbounded in z. As in OpenSCAD, zero or negative sizes make an
//! empty shape (with a warning).

use glam::{DVec2, DVec3};
use qcsg_csg::{Aabb, Dag, NodeId, Source};
use qcsg_quadric::Quadric;

use crate::primitives::{ArgLookup, BuildResult, Built};
use crate::value::Value;

/// Whether `name` is a 2-D primitive built here.
pub fn is_2d_primitive(name: &str) -> bool {
    matches!(name, "square" | "circle" | "polygon")
}

/// The box of a plane box `[min, max]` as a z-invariant solid's: unbounded in z.
pub fn column(min: DVec2, max: DVec2) -> Aabb {
    Aabb::new(min.extend(f64::NEG_INFINITY), max.extend(f64::INFINITY))
}

fn positive(x: f64) -> bool {
    x > 0.0 && x.is_finite()
}

fn leaf(dag: &mut Dag, q: Option<Quadric>, source: Source, bounds: Aabb) -> Result<NodeId, String> {
    let q = q.ok_or("the shape's size is not representable")?;
    Ok(dag.bounded_leaf(q, source, bounds))
}

/// `square(size = 1, center = false)`: `size` a number or `[x, y]`.
pub fn square(dag: &mut Dag, args: &dyn ArgLookup<'_>, source: Source) -> BuildResult {
    let size = match args.get("size") {
        Value::Undef => [1.0; 2],
        Value::Number(s) => [s; 2],
        other => other
            .as_numbers(2)
            .map(|v| [v[0], v[1]])
            .ok_or("square(size) needs a number or a vector of 2 numbers")?,
    };
    if !size.iter().all(|&s| positive(s)) {
        return Ok(Built::Empty(format!(
            "square with size [{}, {}] is empty",
            size[0], size[1]
        )));
    }
    let half = DVec2::from_array(size) / 2.0;
    let centre = if matches!(args.get("center"), Value::Bool(true)) {
        DVec2::ZERO
    } else {
        half
    };
    let mut slabs = Vec::with_capacity(2);
    for (axis, dir) in [DVec3::X, DVec3::Y].into_iter().enumerate() {
        let mut lo = DVec2::NEG_INFINITY;
        let mut hi = DVec2::INFINITY;
        lo[axis] = centre[axis] - half[axis];
        hi[axis] = centre[axis] + half[axis];
        let q = Quadric::slab(centre.extend(0.0), dir, half[axis]);
        slabs.push(leaf(dag, q, source, column(lo, hi))?.into());
    }
    let node = dag.intersection(slabs, source);
    Ok(Built::Node(
        dag.bounded(node, column(centre - half, centre + half)),
    ))
}

/// `circle(r = 1)` or `circle(d = 2)` (`d` wins when both are given, as in OpenSCAD).
pub fn circle(dag: &mut Dag, args: &dyn ArgLookup<'_>, source: Source) -> BuildResult {
    let r = match (args.get("d"), args.get("r")) {
        (Value::Number(d), _) => d / 2.0,
        (Value::Undef, Value::Number(r)) => r,
        (Value::Undef, Value::Undef) => 1.0,
        (Value::Undef, other) | (other, _) => {
            return Err(format!(
                "a radius or diameter must be a number, got {}",
                other.type_name()
            ));
        }
    };
    if !positive(r) {
        return Ok(Built::Empty(format!("circle with radius {r} is empty")));
    }
    let q = Quadric::cylinder(DVec3::ZERO, DVec3::Z, r);
    let b = column(DVec2::splat(-r), DVec2::splat(r));
    Ok(Built::Node(leaf(dag, q, source, b)?))
}
