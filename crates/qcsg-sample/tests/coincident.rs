//! Coverage on flush scenes: pairs of one solid written with surfaces shared by its parts (a
//! cutter flush with a face, a cylinder cut flush at half height, a ball minus a turned copy of
//! itself, a tube bored flush, a union with a flush top, boxes sharing their sides, a cylinder
//! on a coaxial one; `qcsg_testkit::FLUSH_PAIRS`) and without. Each flush scene, also
//! moved by 10⁵ and scaled by 10⁻³, must keep the sampler's guarantee against its own ray-cast
//! reference points, and match the clean scene: every sample lies on the clean solid's surface,
//! and every reference point of the clean solid is within the radius of a sample. The sampler
//! reads shared surfaces as the compiler found them (`Dnf::surfaces`), so a curved flush face
//! is resolved like a flat one.
//!
//! Controls that must *not* merge: the same notch and half cylinder with walls `1e-9` and
//! `1e-6` thick where the cutter was flush; both faces of each wall are sampled.

mod common;

use common::{Strictness, check_guarantee, compile_text, diagonal, reference_points};
use qcsg_csg::Dnf;
use qcsg_quadric::DVec3;
use qcsg_sample::{Sampling, sample};
use qcsg_testkit::{FLUSH_PAIRS, FlushPair};

const STRICTNESS: Strictness = Strictness {
    rays: 1200,
    edge_rays: 300,
    min_refs: 0,
    allow_unresolved_regions: false,
    require_proof: false,
};

/// The splat radius as a share of the diagonal.
const RELATIVE_RADIUS: f64 = 0.1;

/// How a pair is placed: as written, moved far from the origin, or scaled down.
#[derive(Clone, Copy, Debug)]
enum Placement {
    AsWritten,
    Moved,
    Scaled,
}

impl Placement {
    const ALL: [Placement; 3] = [Self::AsWritten, Self::Moved, Self::Scaled];

    fn wrap(self, source: &str) -> String {
        match self {
            Self::AsWritten => source.to_string(),
            Self::Moved => format!("translate([1e5, 1e5, 1e5]) {{ {source} }}"),
            Self::Scaled => format!("scale(1e-3) {{ {source} }}"),
        }
    }
}

fn compile(name: &str, source: &str) -> Dnf {
    compile_text(name, source.to_string()).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Whether `p` lies on the surface of `clean`: within `eps` of it there are points inside and
/// points outside (along the normal, or, at an inner edge where the normal runs along the
/// other face, along one of 26 directions).
fn on_surface(clean: &Dnf, p: DVec3, normal: DVec3, eps: f64) -> bool {
    let around =
        (-1..=1).flat_map(|x| (-1..=1).flat_map(move |y| (-1..=1).map(move |z| (x, y, z))));
    let directions = around
        .filter(|&d| d != (0, 0, 0))
        .map(|(x, y, z)| DVec3::new(x as f64, y as f64, z as f64).normalize());
    let (mut inside, mut outside) = (false, false);
    for d in std::iter::once(normal)
        .chain(std::iter::once(-normal))
        .chain(directions)
    {
        if clean.contains(p + eps * d) {
            inside = true;
        } else {
            outside = true;
        }
    }
    inside && outside
}

/// How a flush scene's samples differ from its clean twin: samples off the clean surface, and
/// clean reference points that no sample's disc reaches.
fn against_clean(flush: &Sampling, clean: &Dnf, r: f64, diag: f64) -> Result<(), String> {
    let eps = 1e-7 * diag;
    let off: Vec<DVec3> = flush
        .samples
        .iter()
        .filter(|s| !on_surface(clean, s.position, s.normal, eps))
        .map(|s| s.position)
        .collect();
    if !off.is_empty() {
        return Err(format!(
            "{} of {} samples are not on the clean solid's surface, e.g. {:?}",
            off.len(),
            flush.samples.len(),
            &off[..off.len().min(3)]
        ));
    }
    if clean.terms.is_empty() {
        return Ok(());
    }
    let refs = reference_points(clean, 1200, 5);
    if refs.len() < 100 {
        return Err(format!(
            "only {} reference points on the clean solid",
            refs.len()
        ));
    }
    let slack = 1e-9 * diag;
    let missing = refs
        .iter()
        .filter(|point| {
            !flush
                .samples
                .iter()
                .any(|s| (s.position - point.position).length() <= s.radius + slack)
        })
        .count();
    if missing > 0 {
        return Err(format!(
            "{missing} of {} reference points of the clean solid are in no sample's disc (r = {r})",
            refs.len()
        ));
    }
    Ok(())
}

#[test]
fn flush_scenes_are_sampled_as_their_clean_twins() {
    let mut failures = Vec::new();
    for &FlushPair {
        name, flush, clean, ..
    } in FLUSH_PAIRS
    {
        for placement in Placement::ALL {
            let flush_dnf = compile(name, &placement.wrap(flush));
            let clean_dnf = compile(name, &placement.wrap(clean));
            let label = format!("{name} {placement:?}");
            if clean_dnf.terms.is_empty() {
                // Nothing to sample: the flush scene must be empty too.
                let sampling = sample(&flush_dnf, 1.0).expect("valid radius");
                if !sampling.samples.is_empty() {
                    failures.push(format!(
                        "{label}: {} samples of an empty solid",
                        sampling.samples.len()
                    ));
                }
                continue;
            }
            let diag = diagonal(&clean_dnf);
            let r = RELATIVE_RADIUS * diag;
            let sampling = sample(&flush_dnf, r).expect("valid radius");
            eprintln!(
                "{label}: {} samples, {} queries, {} unresolved",
                sampling.samples.len(),
                sampling.stats.subdivision.distance_queries,
                sampling.stats.unresolved()
            );
            if let Err(message) = check_guarantee(&flush_dnf, &sampling, r, STRICTNESS) {
                failures.push(format!("{label}: {message}"));
            }
            if let Err(message) = against_clean(&sampling, &clean_dnf, r, diag) {
                failures.push(format!("{label}: {message}"));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A wall's inner face: the signed offset of a point from it and the solid's outward normal
/// there.
type Face = fn(DVec3, f64) -> (f64, DVec3);

/// Walls `gap` thick where the pairs' cutters were flush: the notch's side wall and the half
/// cylinder's shell, each with its inner face (the cutter's surface, `gap` from the part's).
fn walls(gap: f64) -> [(String, String, Face); 2] {
    [
        (
            format!("notch with walls {gap:e} thick"),
            format!(
                "difference() {{ cube([20, 10, 10]); \
                 translate([5, {gap:e}, 5]) cube([10, 10 - 2 * {gap:e}, 5]); }}"
            ),
            |p, gap| {
                let inside = (6.0..14.0).contains(&p.x) && (5.5..9.5).contains(&p.z);
                (if inside { p.y - gap } else { f64::INFINITY }, DVec3::Y)
            },
        ),
        (
            format!("half cylinder with a shell {gap:e} thick"),
            format!(
                "difference() {{ cylinder(h = 10, r = 5); \
                 translate([0, 0, 5]) cylinder(h = 5, r = 5 - {gap:e}); }}"
            ),
            |p, gap| {
                let radial = DVec3::new(p.x, p.y, 0.0);
                let offset = if (5.5..9.5).contains(&p.z) {
                    radial.length() - (5.0 - gap)
                } else {
                    f64::INFINITY
                };
                (offset, -radial.normalize_or_zero())
            },
        ),
    ]
}

#[test]
fn thin_walls_where_a_cutter_was_flush_are_not_merged() {
    let mut failures = Vec::new();
    for gap in [1e-9, 1e-6] {
        for (name, source, face) in walls(gap) {
            let dnf = compile(&name, &source);
            let diag = diagonal(&dnf);
            let r = RELATIVE_RADIUS * diag;
            let sampling = sample(&dnf, r).expect("valid radius");
            if let Err(message) = check_guarantee(&dnf, &sampling, r, STRICTNESS) {
                failures.push(format!("{name}: {message}"));
            }
            // Samples facing into the cut on the wall's inner face; the outer face is `gap`
            // away, with the opposite normal.
            let on_inner = (sampling.samples.iter())
                .filter(|s| {
                    let (offset, normal) = face(s.position, gap);
                    offset.abs() <= 0.25 * gap && s.normal.dot(normal) > 0.99
                })
                .count();
            eprintln!(
                "{name}: {} samples, {on_inner} on the inner face, {} unresolved",
                sampling.samples.len(),
                sampling.stats.unresolved()
            );
            if on_inner == 0 {
                failures.push(format!("{name}: no sample on the wall's inner face"));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
