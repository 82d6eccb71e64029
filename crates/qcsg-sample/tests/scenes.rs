//! The guarantee on programs and on random scenes: every example in `examples/`, the stiff
//! scenes of `tests/stability/` and `crates/qcsg-splat/tests/scenes/`, and seeded random CSG
//! trees of ellipsoids, cylinders, boxes and cone frusta under random rigid motions. Each is
//! compiled to its DNF, sampled with a radius relative to its diagonal, and checked by
//! [`common::check_guarantee`]: samples on their quadric and on the CSG surface, and reference
//! points from ray casting the DNF (independent of the sampler), feature curves included, each
//! within `r` of a sample on the same quadric. Every failing scene is named in one report.

mod common;

use std::path::{Path, PathBuf};

use common::{Checked, Rng, Strictness, check_guarantee, compile_file, diagonal, programs_in};
use qcsg_csg::{Aabb, Dag, Dnf, DnfOptions, Edge, build_dnf};
use qcsg_quadric::{DMat4, DVec3, Quadric};
use qcsg_sample::sample;

/// Radius relative to the scene diagonal for the programs: coarse, so that a debug build copes.
const RELATIVE_RADIUS: f64 = 0.1;

/// Programs expected to produce no solid (their header says `expect: empty` or an error).
fn expects_a_solid(path: &Path) -> bool {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    !text
        .lines()
        .take_while(|l| l.starts_with("//"))
        .any(|l| l.contains("expect: empty") || l.contains("expect: error"))
}

/// Samples and checks one DNF; a line for the log or the failure.
fn check_dnf(
    name: &str,
    dnf: &Dnf,
    relative: f64,
    strictness: Strictness,
) -> Result<String, String> {
    let r = relative * diagonal(dnf);
    let sampling = sample(dnf, r).map_err(|e| format!("{name}: {e}"))?;
    let stats = sampling.stats;
    match check_guarantee(dnf, &sampling, r, strictness) {
        Ok(Checked {
            samples,
            refs,
            edges,
        }) => Ok(format!(
            "{name}: {} quadrics, {} terms, {samples} samples, {} queries, {refs} reference and \
             {edges} edge points covered; given up: {} rectangles proven covered, {} unproven, \
             {} region rectangles around apices",
            dnf.quadrics.len(),
            dnf.terms.len(),
            stats.subdivision.distance_queries,
            stats.subdivision.unresolved_covered,
            stats.subdivision.unresolved,
            stats.regions.unresolved
        )),
        Err(message) => Err(format!("{name}: {message}")),
    }
}

/// The strictness for programs: the unproven-rectangle counter is reported, not required to be
/// zero (see [`Strictness::require_proof`]); coverage is checked in full.
const PROGRAMS: Strictness = Strictness {
    rays: 2500,
    edge_rays: 800,
    min_refs: 200,
    allow_unresolved_regions: true,
    require_proof: false,
};

/// [`PROGRAMS`], and nothing may be left unproven.
const PROVEN: Strictness = Strictness {
    allow_unresolved_regions: false,
    require_proof: true,
    ..PROGRAMS
};

/// Checks every program in `files` that should produce a solid; panics naming all failures.
fn check_programs(files: &[PathBuf], relative: f64) {
    check_programs_with(files, relative, PROGRAMS);
}

/// [`check_programs`] with `strictness`.
fn check_programs_with(files: &[PathBuf], relative: f64, strictness: Strictness) {
    assert!(!files.is_empty(), "no programs");
    let mut failures = Vec::new();
    let mut checked = 0;
    for path in files {
        let name = path
            .strip_prefix(common::workspace_root())
            .unwrap_or(path)
            .to_string_lossy()
            .into_owned();
        if !expects_a_solid(path) {
            continue;
        }
        let dnf = match compile_file(path) {
            Ok(dnf) => dnf,
            Err(message) => {
                failures.push(format!("{name}: does not compile: {message}"));
                continue;
            }
        };
        match check_dnf(&name, &dnf, relative, strictness) {
            Ok(line) => eprintln!("{line}"),
            Err(failure) => failures.push(failure),
        }
        checked += 1;
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(checked > 0);
}

/// Covers the coincident faces of `customizer_box.qcsg` and `openscad_bracket.scad` (minimal
/// variants: `tests/shared_faces.rs`), and nothing may be left unproven. All three program sets
/// take about 8 s in a debug build.
#[test]
fn every_example() {
    check_programs_with(&programs_in("examples"), RELATIVE_RADIUS, PROVEN);
}

#[test]
fn every_stability_scene() {
    check_programs(&programs_in("tests/stability"), RELATIVE_RADIUS);
}

/// Covers the coincident faces of `coincident_faces.qcsg`, and nothing may be left unproven.
#[test]
fn every_splat_renderer_scene() {
    check_programs_with(
        &programs_in("crates/qcsg-splat/tests/scenes"),
        RELATIVE_RADIUS,
        PROVEN,
    );
}

/// A random part in its own frame, bounded, then moved by a random rigid motion.
fn random_part(dag: &mut Dag, rng: &mut Rng) -> Edge {
    let at = common::at;
    let leaf = |dag: &mut Dag, q: Option<Quadric>| -> Edge {
        dag.leaf(q.expect("valid quadric"), at()).into()
    };
    let (node, half) = match rng.next_u64() % 4 {
        0 => {
            let radii = DVec3::new(
                rng.range(0.3, 1.0),
                rng.range(0.3, 1.0),
                rng.range(0.3, 1.0),
            );
            let e = leaf(dag, Quadric::ellipsoid(DVec3::ZERO, radii));
            let node = dag.intersection([e], at());
            (node, radii)
        }
        1 => {
            let (r, h) = (rng.range(0.2, 0.7), rng.range(0.3, 1.0));
            let c = leaf(dag, Quadric::cylinder(DVec3::ZERO, DVec3::Z, r));
            let s = leaf(dag, Quadric::slab(DVec3::ZERO, DVec3::Z, h));
            (dag.intersection([c, s], at()), DVec3::new(r, r, h))
        }
        2 => {
            let half = DVec3::new(
                rng.range(0.3, 0.9),
                rng.range(0.3, 0.9),
                rng.range(0.3, 0.9),
            );
            let slabs: Vec<Edge> = [(DVec3::X, half.x), (DVec3::Y, half.y), (DVec3::Z, half.z)]
                .into_iter()
                .map(|(n, w)| leaf(dag, Quadric::slab(DVec3::ZERO, n, w)))
                .collect();
            (dag.intersection(slabs, at()), half)
        }
        _ => {
            // A frustum of a cone whose apex lies below the slab.
            let slope = rng.range(0.3, 1.0);
            let h = rng.range(0.3, 0.8);
            let apex = DVec3::new(0.0, 0.0, -h - rng.range(0.1, 0.5));
            let c = leaf(dag, Quadric::cone(apex, DVec3::Z, slope));
            let s = leaf(dag, Quadric::slab(DVec3::ZERO, DVec3::Z, h));
            let reach = slope * (2.0 * h - apex.z - h);
            (dag.intersection([c, s], at()), DVec3::new(reach, reach, h))
        }
    };
    let node = dag.bounded(node, Aabb::new(-half, half));
    let motion =
        DMat4::from_translation(DVec3::new(
            rng.range(-0.6, 0.6),
            rng.range(-0.6, 0.6),
            rng.range(-0.6, 0.6),
        )) * DMat4::from_axis_angle(rng.direction(), rng.range(0.0, std::f64::consts::TAU));
    dag.transformed(node.into(), &motion).expect("rigid motion")
}

/// A random CSG tree of 2 to 4 parts, combined left to right by union, intersection or
/// difference.
fn random_scene(seed: u64) -> Option<Dnf> {
    let mut rng = Rng::new(seed);
    let mut dag = Dag::new();
    let parts = 2 + (rng.next_u64() % 3) as usize;
    let mut solid = random_part(&mut dag, &mut rng);
    for _ in 1..parts {
        let part = random_part(&mut dag, &mut rng);
        let node = match rng.next_u64() % 3 {
            0 => dag.union([solid, part], common::at()),
            1 => dag.intersection([solid, part], common::at()),
            _ => dag.difference([solid, part], common::at()),
        };
        solid = node.into();
    }
    dag.set_root(solid);
    build_dnf(&dag, &DnfOptions::default())
        .ok()
        .filter(|dnf| !dnf.terms.is_empty() && diagonal(dnf).is_finite())
}

#[test]
fn random_scenes() {
    let strictness = Strictness {
        rays: 1500,
        edge_rays: 600,
        min_refs: 0,
        // Frusta rotated in their box can bring a cone's apex into the term's box.
        allow_unresolved_regions: true,
        // Terms sharing a quadric make eq. 22 touch zero along curves (see `Strictness`).
        require_proof: false,
    };
    let mut failures = Vec::new();
    let mut solids = 0;
    for seed in 0..16u64 {
        let Some(dnf) = random_scene(seed) else {
            continue;
        };
        solids += 1;
        match check_dnf(&format!("random scene {seed}"), &dnf, 0.05, strictness) {
            Ok(line) => eprintln!("{line}"),
            Err(failure) => failures.push(failure),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(
        solids >= 10,
        "only {solids} of 16 random scenes have a solid"
    );
}

/// The examples again at a tenth of that radius, where the subdivision goes ten times deeper
/// into the contacts between parts that eq. 22 resolves ([`qcsg_sample::csg_distance`]). Every
/// rectangle must be proven there: the tangent, touching and offset surfaces of the examples,
/// the apices of their cones and the points where three parts meet are all settled.
#[test]
fn every_example_at_a_fine_radius() {
    check_programs_with(&programs_in("examples"), RELATIVE_RADIUS / 10.0, PROVEN);
}
