//! The DNF means what the DAG means: for random scenes and random points, membership by direct
//! evaluation of the DAG equals membership by the DNF (points within rounding distance of any
//! surface are skipped, where the two may legitimately differ). The same holds with every
//! pruning rule off and with each rule off alone.

mod common;

use common::{cube, cylinder, sphere, src};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use qcsg_csg::dnf::Pruning;
use qcsg_csg::{Aabb, Dag, DnfOptions, Edge, NodeId, build_dnf};
use qcsg_quadric::{DMat4, DVec3, Quadric};
use qcsg_testkit::Rng;

fn config(cases: u32) -> Config {
    Config {
        cases,
        rng_seed: RngSeed::Fixed(0x0c5a_6000),
        failure_persistence: None,
        ..Config::default()
    }
}

/// A point uniform in the cube `[lo, hi]³`.
fn vec(rng: &mut Rng, lo: f64, hi: f64) -> DVec3 {
    rng.in_box(DVec3::splat(lo), DVec3::splat(hi))
}

/// A random placement: translation, rotation (sometimes by exact quarter turns), scale.
fn placement(rng: &mut Rng) -> DMat4 {
    let translation = DMat4::from_translation(vec(rng, -3.0, 3.0));
    let rotation = match rng.below(3) {
        0 => DMat4::IDENTITY,
        1 => {
            let quarter = DMat4::from_cols_array(&[
                0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
            ]);
            if rng.below(2) == 0 {
                quarter
            } else {
                quarter * quarter
            }
        }
        _ => {
            DMat4::from_rotation_z(rng.range(-3.0, 3.0))
                * DMat4::from_rotation_y(rng.range(-3.0, 3.0))
                * DMat4::from_rotation_x(rng.range(-3.0, 3.0))
        }
    };
    let scale = if rng.below(3) == 0 {
        DMat4::from_scale(vec(rng, 0.5, 2.0))
    } else {
        DMat4::IDENTITY
    };
    translation * rotation * scale
}

/// Builds a random solid; records every leaf's world quadric in `leaves`.
fn random_solid(
    dag: &mut Dag,
    rng: &mut Rng,
    depth: u32,
    world: DMat4,
    leaves: &mut Vec<Quadric>,
    pool: &mut Vec<(NodeId, Vec<Quadric>)>,
) -> NodeId {
    let leaf_choice = depth == 0 || rng.below(4) == 0;
    if leaf_choice {
        // Sometimes reuse an earlier node (exercises sharing).
        if !pool.is_empty() && rng.below(4) == 0 {
            let (node, local) = pool[rng.below(pool.len())].clone();
            leaves.extend(local.iter().filter_map(|q| q.transformed(&world)));
            return node;
        }
        let before = dag.len();
        let node = match rng.below(4) {
            0 => sphere(dag, rng.range(0.5, 2.5), 0),
            1 => cube(dag, vec(rng, 0.5, 3.0), 1),
            2 => cylinder(dag, rng.range(0.3, 1.5), rng.range(0.5, 3.0), 2),
            _ => {
                let q = Quadric::half_space(vec(rng, -1.0, 1.0), vec(rng, -1.0, 1.0)).unwrap();
                dag.leaf(q, src(3))
            }
        };
        let local: Vec<Quadric> = dag.nodes()[before.min(dag.len())..]
            .iter()
            .filter_map(|n| match &n.kind {
                qcsg_csg::NodeKind::Leaf(q) => Some(*q),
                _ => None,
            })
            .collect();
        leaves.extend(local.iter().filter_map(|q| q.transformed(&world)));
        pool.push((node, local));
        return node;
    }
    let count = 1 + rng.below(3);
    let mut children: Vec<Edge> = Vec::new();
    for _ in 0..count {
        let m = placement(rng);
        let child = random_solid(dag, rng, depth - 1, world * m, leaves, pool);
        children.push(dag.edge(child, &m).unwrap());
    }
    match rng.below(7) {
        0 | 1 => dag.union(children, src(10)),
        5 => {
            let u = dag.union(children, src(15));
            dag.color(u.into(), [rng.unit(), rng.unit(), rng.unit(), 1.0], src(16))
                .unwrap()
        }
        6 => {
            let u = dag.intersection(children, src(17));
            dag.highlight(u.into(), src(18))
        }
        2 => dag.intersection(children, src(11)),
        3 => dag.difference(children, src(12)),
        _ => {
            let c = dag.union(children, src(13));
            dag.complement(c.into(), src(14))
        }
    }
}

/// Builds a scene cut to a box (so complements and half-spaces stay bounded) and compares.
fn check_scene(seed: u64, points: usize, options: &DnfOptions) -> Result<(), TestCaseError> {
    let mut rng = Rng::new(seed);
    let mut dag = Dag::new();
    let mut leaves = Vec::new();
    let mut pool = Vec::new();
    let depth = 1 + rng.below(4) as u32;
    let body = random_solid(
        &mut dag,
        &mut rng,
        depth,
        DMat4::IDENTITY,
        &mut leaves,
        &mut pool,
    );
    let frame = cube(&mut dag, DVec3::splat(16.0), 99);
    let frame_edge = dag.translated(frame.into(), DVec3::splat(-8.0)).unwrap();
    let root = dag.intersection([body.into(), frame_edge], src(100));
    dag.set_root(root.into());
    for axis in 0..3 {
        let mut normal = DVec3::ZERO;
        normal[axis] = 1.0;
        leaves.push(Quadric::slab(DVec3::ZERO, normal, 8.0).unwrap());
    }
    let dnf = match build_dnf(&dag, options) {
        Ok(dnf) => dnf,
        // Deep random scenes may legitimately need more terms than the limit.
        Err(errors) if errors.iter().all(|e| e.code == qcsg_csg::codes::TERM_LIMIT) => {
            return Ok(());
        }
        Err(errors) => {
            prop_assert!(false, "seed {seed}: {errors:?}");
            unreachable!()
        }
    };
    let mut compared = 0;
    for _ in 0..points {
        let p = match options.region {
            Some(r) => r.min + (r.max - r.min) * DVec3::new(rng.unit(), rng.unit(), rng.unit()),
            None => vec(&mut rng, -9.0, 9.0),
        };
        let near = leaves
            .iter()
            .any(|q| q.conservative_distance(p).abs() < 1e-6);
        if near {
            continue;
        }
        compared += 1;
        // Every term holding at p has p in its box.
        for term in &dnf.terms {
            let holds = term
                .literals
                .iter()
                .all(|&id| dnf.quadrics[id as usize].quadric.value(p) <= 0.0);
            if holds {
                prop_assert!(
                    term.bounds.contains(p),
                    "seed {} point {} outside its term's box {:?}",
                    seed,
                    p,
                    term.bounds
                );
            }
        }
        prop_assert_eq!(
            dag.contains(p),
            dnf.contains(p),
            "seed {} point {} ({} terms)",
            seed,
            p,
            dnf.terms.len()
        );
    }
    prop_assert!(compared > 0 || points == 0);
    Ok(())
}

proptest! {
    #![proptest_config(config(200))]

    #[test]
    fn dnf_membership_equals_dag_membership(seed in any::<u64>()) {
        check_scene(seed, 200, &DnfOptions::default())?;
    }

    #[test]
    fn unpruned_dnf_has_the_same_meaning(seed in any::<u64>()) {
        check_scene(seed, 100, &DnfOptions { prune: false, ..DnfOptions::default() })?;
    }

    #[test]
    fn region_dnf_is_exact_inside_its_region(seed in any::<u64>(), corner in prop::array::uniform3(-6.0f64..2.0)) {
        let min = DVec3::from_array(corner);
        let region = Aabb::new(min, min + DVec3::splat(4.0));
        check_scene(seed, 200, &DnfOptions { region: Some(region), ..DnfOptions::default() })?;
    }
}

/// All pruning off, then each rule off alone: a smaller term limit keeps the multiplied-out
/// scenes cheap (those over it are skipped like any scene over the limit).
fn switch_sets() -> Vec<(&'static str, Pruning)> {
    let mut sets = vec![("none", Pruning::none())];
    for name in Pruning::RULES {
        sets.push((name, Pruning::without(name).unwrap()));
    }
    sets
}

proptest! {
    #![proptest_config(config(40))]

    #[test]
    fn every_pruning_switch_keeps_the_meaning(seed in any::<u64>()) {
        for (name, pruning) in switch_sets() {
            let options = DnfOptions { term_limit: 5_000, pruning, ..DnfOptions::default() };
            check_scene(seed, 60, &options).map_err(|e| {
                TestCaseError::fail(format!("pruning off: {name}: {e}"))
            })?;
        }
    }
}

#[test]
fn pruning_names_round_trip() {
    assert_eq!(Pruning::default(), Pruning::all());
    for name in Pruning::RULES {
        let off = Pruning::without(name).unwrap();
        assert_ne!(off, Pruning::all(), "{name}");
        let mut back = off;
        assert!(back.set(name, true));
        assert_eq!(back, Pruning::all(), "{name}");
    }
    assert!(Pruning::without("no_such_rule").is_none());
    let mut none = Pruning::none();
    for name in Pruning::RULES {
        assert!(none.set(name, true));
    }
    assert_eq!(none, Pruning::all());
}
