//! Each pruning step removes what it should and nothing else: counts in the stats, and
//! membership unchanged against the DAG.

mod common;

use common::{cube, sphere, src};
use qcsg_csg::dnf::Pruning;
use qcsg_csg::{Aabb, Dag, Dnf, DnfOptions, build_dnf, build_dnf_of, codes};
use qcsg_quadric::{DVec3, Quadric};

/// Compares DNF and DAG membership on a grid (with an irrational offset, so that no grid point
/// lies on the axis-aligned surfaces of these scenes).
fn assert_same_meaning(dag: &Dag, dnf: &Dnf, probe: Aabb) {
    assert_same_meaning_at(dag, dnf, probe, 23);
}

fn assert_same_meaning_at(dag: &Dag, dnf: &Dnf, probe: Aabb, n: usize) {
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let t = (DVec3::new(i as f64, j as f64, k as f64) + 0.137_035_999) / n as f64;
                let p = probe.min + t * (probe.max - probe.min);
                assert_eq!(dag.contains(p), dnf.contains(p), "at {p}");
            }
        }
    }
}

fn pass<'a>(dnf: &'a Dnf, name: &str) -> &'a qcsg_csg::stats::PassStats {
    dnf.stats.passes.iter().find(|p| p.pass == name).unwrap()
}

fn probe() -> Aabb {
    Aabb::new(DVec3::splat(-4.0), DVec3::splat(4.0))
}

#[test]
fn disjoint_intersection_is_empty_by_bounds() {
    let mut dag = Dag::new();
    let a = sphere(&mut dag, 1.0, 0);
    let b = sphere(&mut dag, 1.0, 1);
    let b = dag.translated(b.into(), DVec3::new(3.0, 0.0, 0.0)).unwrap();
    let i = dag.intersection([a.into(), b], src(2));
    dag.set_root(i.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    assert!(dnf.terms.is_empty());
    assert_eq!(dnf.stats.construction.terms_outside_operand_bounds, 1);
    assert!(dnf.quadrics.is_empty(), "nothing left to draw");
    assert_same_meaning(&dag, &dnf, probe());
}

#[test]
fn literal_false_over_the_box_removes_the_term() {
    let mut dag = Dag::new();
    let s = sphere(&mut dag, 1.0, 0);
    // x + y ≥ 4: tilted, so its own box is all of space, and it misses the sphere.
    let h = dag.leaf(
        Quadric::half_space(DVec3::new(2.0, 2.0, 0.0), DVec3::new(-1.0, -1.0, 0.0)).unwrap(),
        src(1),
    );
    let kept = sphere(&mut dag, 0.5, 2);
    let kept = dag
        .translated(kept.into(), DVec3::new(0.0, 3.0, 0.0))
        .unwrap();
    let i = dag.intersection([s.into(), h.into()], src(3));
    let u = dag.union([i.into(), kept], src(4));
    dag.set_root(u.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    assert_eq!(dnf.terms.len(), 1);
    assert_eq!(dnf.stats.construction.terms_outside_literal, 1);
    assert_same_meaning(&dag, &dnf, probe());
}

#[test]
fn literal_true_over_the_box_is_dropped_and_nothing_else() {
    let mut dag = Dag::new();
    let s = sphere(&mut dag, 1.0, 0);
    // x ≤ 1.5 contains the sphere: redundant. x ≤ 0.5 cuts it: kept.
    let loose = dag.leaf(
        Quadric::half_space(DVec3::new(1.5, 0.0, 0.0), DVec3::X).unwrap(),
        src(1),
    );
    let tight = dag.leaf(
        Quadric::half_space(DVec3::new(0.5, 0.0, 0.0), DVec3::X).unwrap(),
        src(2),
    );
    let i = dag.intersection([s.into(), loose.into(), tight.into()], src(3));
    dag.set_root(i.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    assert_eq!(dnf.terms.len(), 1);
    assert_eq!(dnf.terms[0].literals.len(), 2);
    assert_eq!(dnf.stats.construction.literals_inside, 1);
    assert!(dnf.quadrics.iter().all(|q| q.source != src(1)));
    assert_same_meaning(&dag, &dnf, probe());

    // The same redundancy met before the bounding literal is left to the final pass.
    let late = dag.intersection([loose.into(), tight.into(), s.into()], src(5));
    dag.set_root(late.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    let p = pass(&dnf, "literal_bounds");
    assert_eq!((p.literals_before, p.literals_after), (3, 2));
    assert_eq!(dnf.terms[0].literals.len(), 2);
    assert_same_meaning(&dag, &dnf, probe());
}

#[test]
fn cube_slabs_are_never_dropped_by_their_own_box() {
    let mut dag = Dag::new();
    let c = cube(&mut dag, DVec3::new(1.0, 2.0, 3.0), 0);
    dag.set_root(c.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    assert_eq!(dnf.terms[0].literals.len(), 3);
    assert_same_meaning(&dag, &dnf, probe());
}

#[test]
fn equal_quadrics_merge_up_to_positive_scale_only() {
    let mut dag = Dag::new();
    let q = Quadric::sphere(DVec3::ZERO, 1.0).unwrap();
    let scaled = Quadric::new(q.origin(), q.coefficients().map(|c| 3.0 * c)).unwrap();
    let a = dag.leaf(q, src(0));
    let b = dag.leaf(scaled, src(1));
    let c = dag.leaf(Quadric::sphere(DVec3::ZERO, 2.0).unwrap(), src(2));
    let i = dag.intersection([a.into(), b.into(), c.into()], src(3));
    dag.set_root(i.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    // a and b are one quadric; the radius-2 sphere contains the term's box only partly (box
    // corners lie outside it), so it stays unless proved redundant.
    assert_eq!(dnf.stats.construction.literals_merged, 1);
    assert!(dnf.terms[0].literals.len() <= 2);
    assert_same_meaning(&dag, &dnf, probe());

    // A complement is never merged with the quadric itself.
    let not_a = dag.complement(a.into(), src(4));
    let d = dag.intersection([b.into(), not_a.into()], src(5));
    let u = dag.union([d.into(), c.into()], src(6));
    dag.set_root(u.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    assert_eq!(dnf.stats.construction.literals_merged, 0);
    assert_same_meaning(&dag, &dnf, probe());
}

#[test]
fn duplicate_and_subsumed_terms_go_and_unused_quadrics_with_them() {
    let mut dag = Dag::new();
    let a = sphere(&mut dag, 1.0, 0);
    let a_again = sphere(&mut dag, 1.0, 1);
    let b = sphere(&mut dag, 1.0, 2);
    let b = dag.translated(b.into(), DVec3::new(0.5, 0.0, 0.0)).unwrap();
    let a_and_b = dag.intersection([a.into(), b], src(3));
    let u = dag.union([a.into(), a_again.into(), a_and_b.into()], src(4));
    dag.set_root(u.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    assert_eq!(dnf.terms.len(), 1);
    assert_eq!(dnf.terms[0].literals, vec![0]);
    assert_eq!(dnf.stats.construction.terms_duplicate, 1);
    assert_eq!(dnf.stats.construction.terms_subsumed, 1);
    let unused = pass(&dnf, "unused_quadrics");
    assert_eq!((unused.quadrics_before, unused.quadrics_after), (2, 1));
    assert_same_meaning(&dag, &dnf, probe());
}

#[test]
fn subtracted_parts_away_from_the_left_side_are_skipped() {
    let mut dag = Dag::new();
    let block = cube(&mut dag, DVec3::new(10.0, 1.0, 1.0), 0);
    let mut children = vec![block.into()];
    for i in 0..40 {
        let hole = sphere(&mut dag, 0.3, 1);
        // Ten holes in the block, thirty far away.
        let x = if i < 10 {
            0.5 + i as f64
        } else {
            100.0 + i as f64
        };
        children.push(
            dag.translated(hole.into(), DVec3::new(x, 0.5, 0.5))
                .unwrap(),
        );
    }
    let d = dag.difference(children, src(2));
    dag.set_root(d.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    assert_eq!(dnf.stats.construction.operands_skipped, 30);
    assert_eq!(dnf.terms.len(), 1);
    assert_eq!(dnf.terms[0].literals.len(), 3 + 10);
    assert_same_meaning(
        &dag,
        &dnf,
        Aabb::new(DVec3::splat(-1.0), DVec3::new(11.0, 2.0, 2.0)),
    );
}

#[test]
fn switching_a_rule_off_stops_only_that_rule() {
    let mut dag = Dag::new();
    let block = cube(&mut dag, DVec3::new(10.0, 1.0, 1.0), 0);
    let mut children = vec![block.into()];
    for i in 0..4 {
        let hole = sphere(&mut dag, 0.3, 1);
        let x = if i < 2 {
            0.5 + i as f64
        } else {
            100.0 + i as f64
        };
        children.push(
            dag.translated(hole.into(), DVec3::new(x, 0.5, 0.5))
                .unwrap(),
        );
    }
    let d = dag.difference(children, src(2));
    dag.set_root(d.into());
    let build = |pruning: Pruning| {
        build_dnf(
            &dag,
            &DnfOptions {
                pruning,
                ..DnfOptions::default()
            },
        )
        .unwrap()
    };
    // Without region-of-interest pruning the far holes reach the leaf, where their
    // complements hold over the whole block and are not added.
    let dnf = build(Pruning::without("operand_bounds").unwrap());
    assert_eq!(dnf.stats.construction.operands_skipped, 0);
    assert_eq!(dnf.stats.construction.literals_inside, 2);
    assert_eq!(dnf.literal_count(), 3 + 2);
    // With neither, they stay in the term.
    let mut pruning = Pruning::none();
    pruning.final_literal_bounds = true;
    let dnf = build(Pruning::none());
    assert_eq!(dnf.stats.passes.len(), 1, "only the renumbering runs");
    assert_eq!(dnf.literal_count(), 3 + 4);
    assert_same_meaning(
        &dag,
        &dnf,
        Aabb::new(DVec3::splat(-1.0), DVec3::new(11.0, 2.0, 2.0)),
    );
    // The final literal pass alone removes them again.
    let dnf = build(pruning);
    assert_eq!(dnf.literal_count(), 3 + 2);
}

#[test]
fn multiplied_out_grid_stops_at_the_term_limit() {
    let dag = block_minus_grid(0.0);
    let start = std::time::Instant::now();
    let result = build_dnf(
        &dag,
        &DnfOptions {
            term_limit: 10_000,
            pruning: Pruning::none(),
            ..DnfOptions::default()
        },
    );
    match result {
        Ok(dnf) => panic!("{}", dnf.stats),
        Err(errors) => assert_eq!(errors[0].code, codes::TERM_LIMIT),
    }
    assert!(start.elapsed().as_secs_f64() < 10.0);
}

#[test]
fn background_parts_are_not_part_of_the_solid() {
    let mut dag = Dag::new();
    let a = sphere(&mut dag, 1.0, 0);
    let big = sphere(&mut dag, 5.0, 1);
    dag.set_root(a.into());
    dag.add_background(big.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    assert!(!dnf.contains(DVec3::new(3.0, 0.0, 0.0)));
    let background = build_dnf_of(&dag, dag.backgrounds()[0], &DnfOptions::default()).unwrap();
    assert!(background.contains(DVec3::new(3.0, 0.0, 0.0)));
}

/// A block minus a 10×10×10 grid of small cubes.
fn block_minus_grid(jitter: f64) -> Dag {
    let mut dag = Dag::new();
    let block = cube(&mut dag, DVec3::splat(20.0), 0);
    let mut children = vec![block.into()];
    for i in 0..1000 {
        let c = cube(&mut dag, DVec3::splat(0.5), 1);
        let cell = DVec3::new((i % 10) as f64, ((i / 10) % 10) as f64, (i / 100) as f64);
        let wobble = DVec3::new((i % 7) as f64, (i % 11) as f64, (i % 13) as f64) * jitter;
        children.push(
            dag.translated(c.into(), cell * 2.0 + 0.75 + wobble)
                .unwrap(),
        );
    }
    let d = dag.difference(children, src(2));
    dag.set_root(d.into());
    dag
}

#[test]
fn aligned_grid_collapses_through_shared_slabs() {
    // The holes share their slabs per row, so ⋂ (¬Xᵢ ∪ ¬Yⱼ ∪ ¬Zₖ) = ⋂¬Xᵢ ∪ ⋂¬Yⱼ ∪ ⋂¬Zₖ.
    let dag = block_minus_grid(0.0);
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    assert_eq!(dnf.terms.len(), 3, "{}", dnf.stats);
    assert_eq!(dnf.quadrics.len(), 3 + 30);
    assert_same_meaning_at(
        &dag,
        &dnf,
        Aabb::new(DVec3::splat(-1.0), DVec3::splat(21.0)),
        15,
    );
}

#[test]
fn jittered_grid_hits_the_limit_globally_and_works_locally() {
    // Every hole has its own slabs: globally up to 3^1000 terms.
    let dag = block_minus_grid(0.01);
    let options = DnfOptions {
        term_limit: 10_000,
        ..DnfOptions::default()
    };
    let start = std::time::Instant::now();
    match build_dnf(&dag, &options) {
        Ok(dnf) => panic!("{}", dnf.stats),
        Err(errors) => assert_eq!(errors[0].code, codes::TERM_LIMIT),
    }
    assert!(start.elapsed().as_secs_f64() < 10.0);
    // Around one hole, the region-restricted form is small and exact.
    let region = Aabb::new(DVec3::splat(0.25), DVec3::splat(1.75));
    let local = build_dnf(
        &dag,
        &DnfOptions {
            region: Some(region),
            ..options
        },
    )
    .unwrap();
    assert!(local.terms.len() <= 3, "{}", local.stats);
    assert_same_meaning_at(&dag, &local, region, 11);
}

#[test]
fn subtracting_a_slab_complement_shrinks_the_term_box() {
    let mut dag = Dag::new();
    let block = cube(&mut dag, DVec3::new(10.0, 1.0, 1.0), 0);
    // Removes x < 5 through the whole block: the term's box shrinks to x ≥ 5 ...
    let cut = cube(&mut dag, DVec3::new(6.0, 3.0, 3.0), 1);
    let cut = dag
        .translated(cut.into(), DVec3::new(-1.0, -1.0, -1.0))
        .unwrap();
    let mut children = vec![block.into(), cut];
    // ... so holes at x < 5 are skipped, the one at x = 7 is kept.
    for x in [1.0, 2.0, 3.0, 7.0] {
        let hole = sphere(&mut dag, 0.3, 2);
        children.push(
            dag.translated(hole.into(), DVec3::new(x, 0.5, 0.5))
                .unwrap(),
        );
    }
    let d = dag.difference(children, src(3));
    dag.set_root(d.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    assert_eq!(dnf.stats.construction.operands_skipped, 3, "{}", dnf.stats);
    assert_eq!(dnf.terms.len(), 1);
    assert!(dnf.bounds.min.x >= 5.0 - 1e-6, "{:?}", dnf.bounds);
    assert_same_meaning(
        &dag,
        &dnf,
        Aabb::new(DVec3::splat(-1.0), DVec3::new(11.0, 2.0, 2.0)),
    );
}

#[test]
fn duplicate_literal_pass_merges_one_surface_met_in_two_colours() {
    let mut dag = Dag::new();
    let a = sphere(&mut dag, 1.0, 0);
    let red = dag.color(a.into(), [1.0, 0.0, 0.0, 1.0], src(1)).unwrap();
    let blue = dag.color(a.into(), [0.0, 0.0, 1.0, 1.0], src(2)).unwrap();
    let i = dag.intersection([red.into(), blue.into()], src(3));
    dag.set_root(i.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    let p = pass(&dnf, "duplicate_literals");
    assert_eq!((p.literals_before, p.literals_after), (2, 1));
    let unused = pass(&dnf, "unused_quadrics");
    assert_eq!((unused.quadrics_before, unused.quadrics_after), (2, 1));
    assert_same_meaning(&dag, &dnf, probe());
}

#[test]
fn long_terms_stay_fast() {
    // A block minus 3,000 through-holes: one term of about 3,000 literals.
    let mut dag = Dag::new();
    let block = cube(&mut dag, DVec3::new(6001.0, 4.0, 4.0), 0);
    let mut children = vec![block.into()];
    for i in 0..3000 {
        let hole = cube(&mut dag, DVec3::new(1.0, 6.0, 6.0), 1);
        let at = DVec3::new(1.0 + 2.0 * i as f64, -1.0, -1.0);
        children.push(dag.translated(hole.into(), at).unwrap());
    }
    let d = dag.difference(children, src(2));
    dag.set_root(d.into());
    let start = std::time::Instant::now();
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    assert!(start.elapsed().as_secs_f64() < 5.0);
    assert_eq!(dnf.terms.len(), 1);
    assert_eq!(dnf.terms[0].literals.len(), 3 + 3000);
    assert!(dnf.contains(DVec3::new(0.5, 2.0, 2.0)) && !dnf.contains(DVec3::new(1.5, 2.0, 2.0)));
}
