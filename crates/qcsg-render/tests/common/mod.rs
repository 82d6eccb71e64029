//! Scenes built through the builder API that the ray tracer's tests and benchmark share.

use qcsg_csg::{Dag, Edge, Source};
use qcsg_quadric::{DVec3, Quadric};

/// A plate 2 thick centred on the origin, drilled with `n × n` holes of radius 1 at a pitch of
/// 3: one term of `n² + 3` literals.
pub fn drilled_plate(dag: &mut Dag, n: u32) -> Edge {
    let half = 1.5 * f64::from(n);
    let slabs: Vec<Edge> = [(DVec3::X, half), (DVec3::Y, half), (DVec3::Z, 1.0)]
        .into_iter()
        .map(|(normal, half)| {
            let slab = Quadric::slab(DVec3::ZERO, normal, half).expect("slab");
            dag.leaf(slab, Source::default()).into()
        })
        .collect();
    let plate = dag.intersection(slabs, Source::default());
    let mut parts = vec![plate.into()];
    for i in 0..n {
        for j in 0..n {
            let at = |k: u32| 1.5 - half + 3.0 * f64::from(k);
            let hole = Quadric::cylinder(DVec3::new(at(i), at(j), 0.0), DVec3::Z, 1.0);
            parts.push(dag.leaf(hole.expect("cylinder"), Source::default()).into());
        }
    }
    dag.difference(parts, Source::default()).into()
}
