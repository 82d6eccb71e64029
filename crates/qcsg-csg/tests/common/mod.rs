//! Scene helpers shared by the integration tests: primitives built the way the evaluator builds
//! them (fewest exact quadrics, with the primitive's box declared on its node).

#![allow(dead_code)]

use qcsg_csg::{Aabb, Dag, NodeId, Source};
use qcsg_diag::{FileId, Span};
use qcsg_quadric::{DVec3, Quadric};

/// A source at byte `offset` of file 0, so tests can tell leaves apart in diagnostics.
pub fn src(offset: usize) -> Source {
    Source::new(FileId(0), Span::new(offset, offset + 1))
}

/// `cube(size)` spanning `[0, size]` per axis: three slabs and the declared box.
pub fn cube(dag: &mut Dag, size: DVec3, offset: usize) -> NodeId {
    let centre = 0.5 * size;
    let slabs: Vec<_> = (0..3)
        .map(|axis| {
            let mut normal = DVec3::ZERO;
            normal[axis] = 1.0;
            let q = Quadric::slab(centre, normal, 0.5 * size[axis]).unwrap();
            dag.leaf(q, src(offset)).into()
        })
        .collect();
    let node = dag.intersection(slabs, src(offset));
    dag.bounded(node, Aabb::new(DVec3::ZERO, size))
}

/// `sphere(r)` about the origin.
pub fn sphere(dag: &mut Dag, radius: f64, offset: usize) -> NodeId {
    let q = Quadric::sphere(DVec3::ZERO, radius).unwrap();
    dag.bounded_leaf(
        q,
        src(offset),
        Aabb::from_centre_half(DVec3::ZERO, DVec3::splat(radius)),
    )
}

/// `cylinder(h, r)` spanning `z ∈ [0, h]`: an infinite cylinder cut by a slab.
pub fn cylinder(dag: &mut Dag, radius: f64, height: f64, offset: usize) -> NodeId {
    let side = Quadric::cylinder(DVec3::ZERO, DVec3::Z, radius).unwrap();
    let caps = Quadric::slab(DVec3::new(0.0, 0.0, 0.5 * height), DVec3::Z, 0.5 * height).unwrap();
    let side = dag.leaf(side, src(offset));
    let caps = dag.leaf(caps, src(offset));
    let node = dag.intersection([side.into(), caps.into()], src(offset));
    dag.bounded(
        node,
        Aabb::new(
            DVec3::new(-radius, -radius, 0.0),
            DVec3::new(radius, radius, height),
        ),
    )
}
