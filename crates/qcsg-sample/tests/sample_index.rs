//! The second pass's sample index finds what a brute-force search over all samples finds: a
//! sample of the quadric, on the same side, that covers a ball around a query point with a
//! radius of at most `r`. Checked at radii small enough against the spread of the query points
//! that the index has to coarsen its map of wanted cubes, and with samples far from any query.
//! So does a search of the samples near a deferred rectangle's centre for a point near it.
//! The side rule itself ([`SurfacePoint::faces`]) is checked against the normals of random
//! quadrics around random surface points.

mod common;

use common::{Rng, sphere_scene};
use qcsg_quadric::{DVec3, Quadric};
use qcsg_sample::subdivide::{Emitted, SampleIndex, SurfacePoint};
use qcsg_sample::{Sample, Samples};

/// A point of the unit sphere (the scene's only quadric) with its outward normal.
fn on_sphere(direction: DVec3) -> SurfacePoint {
    let n = direction.normalize();
    SurfacePoint::new(n, n)
}

fn sample_at(point: SurfacePoint, radius: f64) -> Sample {
    Sample {
        position: point.position,
        normal: point.normal,
        quadric: 0,
        term: 0,
        radius,
        clip_list: 0,
    }
}

/// Query points spread over the sphere, samples around each (some within `r`, some just
/// beyond, some on the far side) and elsewhere; every query is answered like the brute force.
/// With `boxed`, the samples come in boxes as the first pass makes them ([`Emitted`]): the
/// samples around a query point in one, each other sample in its own, so that the index
/// leaves out the boxes far from every query point, and must not leave out a near one.
fn check(r: f64, queries: usize, seed: u64, boxed: bool) {
    let dnf = sphere_scene();
    let mut rng = Rng::new(seed);
    let centres: Vec<SurfacePoint> = (0..queries).map(|_| on_sphere(rng.direction())).collect();
    let mut samples = Emitted::default();
    for c in &centres {
        for _ in 0..2 {
            let offset = rng.direction() * rng.range(0.0, 2.0 * r);
            let radius = rng.range(0.2, 1.0) * r;
            samples.push(sample_at(on_sphere(c.position + offset), radius));
        }
        samples.box_new();
        // The antipode: near in no sense, and facing away.
        samples.push(sample_at(on_sphere(-c.position), r));
        samples.box_new();
    }
    for _ in 0..queries {
        samples.push(sample_at(on_sphere(rng.direction()), r));
        samples.box_new();
    }
    let keys: Vec<(u32, DVec3)> = centres.iter().map(|c| (0, c.position)).collect();
    let boxes = if boxed { &samples.boxes[..] } else { &[] };
    // Cut into runs at every third box, as the threads of the first pass leave them (no box
    // crosses a run).
    let mut runs = Samples::default();
    for group in samples.boxes.chunks(3) {
        let (start, end) = (group[0].start as usize, group[group.len() - 1].end as usize);
        runs.push_run(samples[start..end].to_vec());
    }
    assert_eq!(runs.len(), samples.len());
    let index = SampleIndex::new(&dnf, (&runs, boxes), &keys, r);
    let (mut covered, mut near) = (0, Vec::new());
    for c in &centres {
        // A part of a deferred rectangle whose centre lies within its extent of the rectangle's
        // is answered from the samples near the rectangle's centre alone.
        let extent = rng.range(0.0, 0.5) * r;
        let part = on_sphere(c.position + rng.direction() * rng.range(0.0, extent));
        if (part.position - c.position).length() <= extent {
            index.near(0, c.position, &mut near);
            let brute = samples.iter().any(|s| {
                s.same_side(part.normal) && (s.position - part.position).length() + extent <= r
            });
            let found = index.cover_among(near.iter().copied(), 0, part, extent);
            assert_eq!(
                found.is_some(),
                brute,
                "r = {r}: the list near {:?} misses a sample covering {:?}",
                c.position,
                part.position
            );
        }
        // Every query of the second pass lies within `r / 2` of its key point.
        let extent = rng.range(0.0, 0.5) * r;
        let brute = samples
            .iter()
            .any(|s| s.same_side(c.normal) && (s.position - c.position).length() + extent <= r);
        let found = index.cover((0, 0), *c, extent);
        assert_eq!(
            found.is_some(),
            brute,
            "r = {r}: the index and the brute force disagree at {:?}",
            c.position
        );
        if let Some((i, needed)) = found {
            let s = &samples[i as usize];
            let reach = (s.position - c.position).length() + extent;
            assert!(
                s.same_side(c.normal),
                "r = {r}: a sample facing away covers"
            );
            assert!(
                reach <= needed * (1.0 + 1e-12) && needed <= r,
                "r = {r}: sample {i} at {reach} from the ball's rim is given radius {needed}"
            );
            covered += 1;
        }
    }
    assert!(
        covered > queries / 5,
        "r = {r}: too few decisive queries ({covered})"
    );
}

#[test]
fn index_matches_brute_force() {
    // Few query points, so that most cubes of the map stay unwanted.
    for seed in 0..40 {
        check(0.05, 50, seed, seed % 2 == 0);
    }
}

#[test]
fn index_matches_brute_force_when_its_map_coarsens() {
    // At r = 1e-4 the query points span 10⁴ fine cubes a side: far more than one map holds.
    for boxed in [false, true] {
        check(1e-4, 400, 100, boxed);
        check(1e-7, 200, 101, boxed);
    }
}

/// The points where the line `origin + t · direction` meets `q`.
fn crossings(q: &Quadric, origin: DVec3, direction: DVec3) -> Vec<DVec3> {
    // q(origin + t d) = a t² + b t + c, from three values of the exact quadratic.
    let (f0, f1, fm) = (
        q.value(origin),
        q.value(origin + direction),
        q.value(origin - direction),
    );
    let (a, b, c) = (0.5 * (f1 + fm) - f0, 0.5 * (f1 - fm), f0);
    let disc = b * b - 4.0 * a * c;
    if a.abs() < 1e-12 || disc < 0.0 {
        return Vec::new();
    }
    let root = disc.sqrt();
    [(-b - root) / (2.0 * a), (-b + root) / (2.0 * a)]
        .into_iter()
        .map(|t| origin + t * direction)
        .collect()
}

/// Within `extent` of a surface point, every normal of the quadric is within
/// `asin(bend · extent)` of the point's: so a sample that [`SurfacePoint::faces`] accepts
/// faces the same side as all of them. Random quadrics of every signature, points near and
/// far from their centres (a cone's apex among them), extents up to where the rule gives up.
#[test]
fn a_facing_sample_faces_every_point_within_the_extent() {
    let mut rng = Rng::new(7);
    let (mut checked, mut spread_seen) = (0, 0.0f64);
    for _ in 0..400 {
        let coefficients: [f64; 10] = std::array::from_fn(|k| match k {
            0..=2 => rng.range(-2.0, 2.0),
            3..=5 => rng.range(-1.0, 1.0),
            6..=8 => rng.range(-0.5, 0.5),
            _ => rng.range(-1.0, 1.0),
        });
        let q = Quadric::new(DVec3::ZERO, coefficients).expect("finite");
        for _ in 0..20 {
            let Some(&c) =
                crossings(&q, rng.direction() * rng.range(0.0, 2.0), rng.direction()).first()
            else {
                continue;
            };
            let Some(point) = SurfacePoint::on(&q, c) else {
                continue;
            };
            let extent = rng.range(0.0, 1.0) / point.bend;
            let spread = point.bend * extent;
            for _ in 0..20 {
                let through = c + rng.direction() * rng.range(0.0, extent);
                for p in crossings(&q, through, rng.direction()) {
                    let Some(normal) = q.normal(p) else { continue };
                    if (p - c).length() > extent {
                        continue;
                    }
                    assert!(
                        normal.dot(point.normal) >= (1.0 - spread * spread).sqrt() - 1e-9,
                        "{q:?}: the normal at {p} turns past asin({spread}) from the one at {c}"
                    );
                    checked += 1;
                    spread_seen = spread_seen.max((p - c).length() * point.bend);
                }
            }
        }
    }
    assert!(checked > 10_000, "only {checked} pairs of points checked");
    assert!(
        spread_seen > 0.9,
        "the pairs never came near the rule's limit"
    );
}
