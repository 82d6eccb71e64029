//! Clip lists: every other literal of a sample's term whose surface reaches into the sample's
//! radius is in the sample's list (checked on random points of the sample's quadric within its
//! radius that lie outside that literal), lists are shared, and the buffer is well formed.

mod common;

use std::collections::HashSet;

use common::{Rng, diagonal, points_on};
use qcsg_csg::{Aabb, Dnf};
use qcsg_quadric::DVec3;
use qcsg_sample::{Sampling, sample};

/// Checks the lists of `dnf` sampled at `relative_radius` of the diagonal; returns how many
/// random points fell outside another literal of the sample's term (each a decisive check).
fn check(name: &str, dnf: &Dnf, relative_radius: f64, seed: u64) -> usize {
    let r = relative_radius * diagonal(dnf);
    let sampling = sample(dnf, r).expect("valid radius");
    check_buffer(name, &sampling, dnf);
    let mut rng = Rng::new(seed);
    let mut decisive = 0;
    for s in &sampling.samples {
        let list = sampling.clip_lists.get(s.clip_list).expect("list in range");
        let term = &dnf.terms[s.term as usize];
        let q = dnf.quadrics[s.quadric as usize].quadric;
        let around = Aabb::from_centre_half(s.position, DVec3::splat(s.radius));
        for p in points_on(&q, &around, 6, &mut rng) {
            if (p - s.position).length() > s.radius {
                continue;
            }
            for &j in &term.literals {
                if j == s.quadric || dnf.quadrics[j as usize].quadric.value(p) <= 0.0 {
                    continue;
                }
                decisive += 1;
                assert!(
                    list.contains(&j),
                    "{name}: a point {p:?} within r = {} of the sample at {:?} (quadric {}, \
                     term {}) is outside literal {j}, which is missing from its list {list:?}",
                    s.radius,
                    s.position,
                    s.quadric,
                    s.term
                );
            }
        }
    }
    decisive
}

/// The buffer is well formed: offsets ascending from 0, indices valid, no list holds its
/// sample's own quadric or a quadric from outside its term, and no list is stored twice.
fn check_buffer(name: &str, sampling: &Sampling, dnf: &Dnf) {
    let lists = &sampling.clip_lists;
    assert_eq!(lists.offsets.first(), Some(&0), "{name}: first offset");
    assert_eq!(
        lists.offsets.last().map(|&o| o as usize),
        Some(lists.indices.len()),
        "{name}: last offset"
    );
    assert!(lists.offsets.windows(2).all(|w| w[0] <= w[1]));
    assert_eq!(
        lists.get(0),
        Some(&[][..]),
        "{name}: list 0 is the empty list"
    );
    let distinct: HashSet<&[u32]> = (0..lists.len() as u32)
        .map(|k| lists.get(k).expect("list"))
        .collect();
    assert_eq!(
        distinct.len(),
        lists.len(),
        "{name}: a list is stored twice"
    );
    assert_eq!(sampling.stats.clip_indices, lists.indices.len() as u64);
    assert_eq!(sampling.stats.clip_lists, lists.len() as u64);
    for s in &sampling.samples {
        let list = lists.get(s.clip_list).expect("list in range");
        let term = &dnf.terms[s.term as usize];
        for &j in list {
            assert_ne!(j, s.quadric, "{name}: own quadric in the clip list");
            assert!(term.literals.contains(&j), "{name}: {j} not in the term");
        }
    }
}

#[test]
fn three_spheres() {
    let decisive = check("three spheres", &common::three_spheres(), 0.05, 1);
    assert!(decisive > 100, "only {decisive} decisive checks");
}

#[test]
fn cube_minus_cylinder() {
    let decisive = check("cube - cylinder", &common::cube_minus_cylinder(), 0.05, 2);
    assert!(decisive > 100, "only {decisive} decisive checks");
    check(
        "cube - cylinder, small r",
        &common::cube_minus_cylinder(),
        0.02,
        3,
    );
}

#[test]
fn cone_slab_and_apex() {
    let decisive = check("cone ∩ slab", &common::cone_slab(), 0.05, 4)
        + check("cone apex", &common::cone_with_apex(), 0.05, 5);
    assert!(decisive > 100, "only {decisive} decisive checks");
}

#[test]
fn far_and_tiny() {
    let decisive =
        check("far", &common::far_scene(), 0.05, 6) + check("tiny", &common::tiny_scene(), 0.05, 7);
    assert!(decisive > 100, "only {decisive} decisive checks");
}

/// A plate drilled with 25 holes is one term of many literals: each span of samples first sorts
/// the literals out by box, and the lists still hold every hole that reaches into a splat.
#[test]
fn many_literals() {
    let text = "difference() {
        cube([10, 10, 1], center = true);
        for (i = [-2:2], j = [-2:2])
            translate([2 * i, 2 * j, 0]) cylinder(h = 2, r = 0.5 + 0.08 * (i + j + 4), center = true);
    }";
    let dnf = common::compile_text("plate.qcsg", text.to_string()).expect("compiles");
    let sizes: Vec<usize> = dnf.terms.iter().map(|t| t.literals.len()).collect();
    assert!(sizes.iter().any(|&n| n > 20), "{sizes:?}");
    let decisive = check("drilled plate", &dnf, 0.02, 8);
    assert!(decisive > 100, "only {decisive} decisive checks");
}

#[test]
fn lists_are_shared() {
    let dnf = common::cube_minus_cylinder();
    let sampling = sample(&dnf, 0.02 * diagonal(&dnf)).expect("sample");
    // Far fewer distinct lists than samples: a term of four literals has at most 8 subsets.
    assert!(sampling.clip_lists.len() <= 8 * dnf.terms.len());
    assert!(sampling.samples.len() > 10 * sampling.clip_lists.len());
}
