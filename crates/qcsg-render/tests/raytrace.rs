//! Ray classification cases that a naive CSG ray caster gets wrong: difference normals, unions
//! that are re-entered, unbounded literals, tangent rays and touching solids, plus determinism
//! across thread counts.

mod common;

use qcsg_csg::{Aabb, Dag, Dnf, DnfOptions, Edge, Source, build_dnf};
use qcsg_quadric::{DVec3, Quadric};
use qcsg_render::raytrace::{LITERAL_INDEX_ABOVE, Scratch, TermIndex, term_index};
use qcsg_render::{
    Camera, Hit, ImageSize, Projection, Ray, RenderOptions, Scene, View, render, trace,
};
use qcsg_testkit::Rng;

fn sphere(dag: &mut Dag, centre: DVec3, radius: f64) -> Edge {
    let q = Quadric::sphere(centre, radius).unwrap();
    let r = DVec3::splat(radius);
    dag.bounded_leaf(q, Source::default(), Aabb::new(centre - r, centre + r))
        .into()
}

fn dnf_of(dag: &mut Dag, root: Edge) -> Dnf {
    dag.set_root(root);
    build_dnf(dag, &DnfOptions::default()).unwrap()
}

fn cast(dnf: &Dnf, origin: DVec3, direction: DVec3) -> Option<Hit> {
    let ray = Ray {
        origin,
        direction: direction.normalize(),
    };
    trace(dnf, &term_index(dnf), &ray, 0.0, &mut Scratch::default())
}

/// The index of the DNF quadric equal to `q` or to its complement.
fn quadric_index(dnf: &Dnf, q: &Quadric) -> u32 {
    dnf.quadrics
        .iter()
        .position(|d| {
            d.quadric.approx_eq_up_to_scale(q, 1e-9)
                || d.quadric.approx_eq_up_to_scale(&q.negated(), 1e-9)
        })
        .expect("quadric in the DNF") as u32
}

#[test]
fn a_difference_shows_the_subtracted_sphere_with_normals_out_of_the_hole() {
    let mut dag = Dag::new();
    let big = sphere(&mut dag, DVec3::ZERO, 2.0);
    let small = sphere(&mut dag, DVec3::new(0.0, 0.0, 1.5), 1.0);
    let solid = dag.difference([big, small], Source::default());
    let dnf = dnf_of(&mut dag, solid.into());
    let hole = Quadric::sphere(DVec3::new(0.0, 0.0, 1.5), 1.0).unwrap();

    // Straight down through the hole: the first surface is the small sphere's bottom, z = 0.5.
    let hit = cast(&dnf, DVec3::new(0.0, 0.0, 5.0), -DVec3::Z).unwrap();
    assert!((hit.t - 4.5).abs() < 1e-9, "{hit:?}");
    assert_eq!(hit.quadric, Some(quadric_index(&dnf, &hole)));
    // Outward from the solid means into the hole, towards the small sphere's centre: +z.
    assert!(hit.normal.z > 0.999, "{hit:?}");

    // Beside the hole, the big sphere's own surface with its outward normal.
    let hit = cast(&dnf, DVec3::new(1.8, 0.0, 5.0), -DVec3::Z).unwrap();
    assert!(hit.normal.z > 0.0 && hit.normal.x > 0.0);
    let expected_z = (4.0f64 - 1.8 * 1.8).sqrt();
    assert!((hit.point.z - expected_z).abs() < 1e-9);
}

#[test]
fn a_union_is_entered_where_the_ray_first_comes_in_also_after_leaving_an_operand() {
    let mut dag = Dag::new();
    // Two caps: a ball without the slab |z| ≤ 1, and a small ball in the gap between them.
    let ball = sphere(&mut dag, DVec3::ZERO, 3.0);
    let slab = dag.leaf(
        Quadric::slab(DVec3::ZERO, DVec3::Z, 1.0).unwrap(),
        Source::default(),
    );
    let caps = dag.difference([ball, slab.into()], Source::default());
    let middle = sphere(&mut dag, DVec3::ZERO, 0.5);
    let solid = dag.union([caps.into(), middle], Source::default());
    let dnf = dnf_of(&mut dag, solid.into());
    let middle_q = quadric_index(&dnf, &Quadric::sphere(DVec3::ZERO, 0.5).unwrap());

    let from_above = cast(&dnf, DVec3::new(0.0, 0.0, 10.0), -DVec3::Z).unwrap();
    assert!((from_above.t - 7.0).abs() < 1e-9);
    // Starting inside the upper cap: the cap is left at z = 1, the small ball entered at 0.5.
    let inside = cast(&dnf, DVec3::new(0.0, 0.0, 2.0), -DVec3::Z).unwrap();
    assert!((inside.t - 1.5).abs() < 1e-9, "{inside:?}");
    assert_eq!(inside.quadric, Some(middle_q));
    assert!(inside.normal.z > 0.999);
    // Starting in the gap below the small ball: the lower cap is re-entered at z = −1.
    let gap = cast(&dnf, DVec3::new(0.0, 0.0, -0.75), -DVec3::Z).unwrap();
    assert!((gap.t - 0.25).abs() < 1e-9, "{gap:?}");
    assert!(
        gap.normal.z > 0.999,
        "the slab's complement faces into the gap: {gap:?}"
    );
}

#[test]
fn overlapping_union_operands_hide_each_others_inner_surfaces() {
    let mut dag = Dag::new();
    let a = sphere(&mut dag, DVec3::ZERO, 5.0);
    let b = sphere(&mut dag, DVec3::new(0.0, 0.0, -5.5), 1.0);
    let solid = dag.union([a, b], Source::default());
    let dnf = dnf_of(&mut dag, solid.into());
    // From the centre of A downwards the ray leaves A inside B and B at z = −6.5: no entry.
    assert_eq!(cast(&dnf, DVec3::ZERO, -DVec3::Z), None);
    // From below, B is entered first.
    let hit = cast(&dnf, DVec3::new(0.0, 0.0, -10.0), DVec3::Z).unwrap();
    assert!((hit.point.z + 6.5).abs() < 1e-9);
}

#[test]
fn a_half_space_cuts_a_sphere() {
    let mut dag = Dag::new();
    let ball = sphere(&mut dag, DVec3::ZERO, 2.0);
    let below = dag.leaf(
        Quadric::half_space(DVec3::ZERO, DVec3::Z).unwrap(),
        Source::default(),
    );
    let solid = dag.intersection([ball, below.into()], Source::default());
    let dnf = dnf_of(&mut dag, solid.into());
    let plane = quadric_index(&dnf, &Quadric::half_space(DVec3::ZERO, DVec3::Z).unwrap());

    let down = cast(&dnf, DVec3::new(0.5, 0.0, 10.0), -DVec3::Z).unwrap();
    assert!((down.t - 10.0).abs() < 1e-9);
    assert_eq!(down.quadric, Some(plane));
    assert!((down.normal - DVec3::Z).length() < 1e-12);
    let up = cast(&dnf, DVec3::new(0.5, 0.0, -10.0), DVec3::Z).unwrap();
    assert!((up.point.z + (4.0f64 - 0.25).sqrt()).abs() < 1e-9);
    assert!(cast(&dnf, DVec3::new(-10.0, 0.0, 1.0), DVec3::X).is_none());
    assert!(cast(&dnf, DVec3::new(-10.0, 0.0, -1.0), DVec3::X).is_some());
}

#[test]
fn tangent_rays_and_touching_solids_make_no_surface() {
    let mut dag = Dag::new();
    let left = sphere(&mut dag, DVec3::new(-1.0, 0.0, 0.0), 1.0);
    let right = sphere(&mut dag, DVec3::new(1.0, 0.0, 0.0), 1.0);
    let union = dag.union([left, right], Source::default());
    let dnf = dnf_of(&mut dag, union.into());
    // Grazing the top of both spheres.
    assert_eq!(cast(&dnf, DVec3::new(-10.0, 0.0, 1.0), DVec3::X), None);
    // From inside the left sphere towards the right one: they touch at the origin, no face.
    assert_eq!(cast(&dnf, DVec3::new(-1.0, 0.0, 0.0), DVec3::X), None);
    // The outer surface is still there.
    let hit = cast(&dnf, DVec3::new(-10.0, 0.0, 0.0), DVec3::X).unwrap();
    assert!((hit.t - 8.0).abs() < 1e-9);

    // Their intersection is a single point: nothing to see.
    let mut dag = Dag::new();
    let left = sphere(&mut dag, DVec3::new(-1.0, 0.0, 0.0), 1.0);
    let right = sphere(&mut dag, DVec3::new(1.0, 0.0, 0.0), 1.0);
    let meet = dag.intersection([left, right], Source::default());
    let dnf = dnf_of(&mut dag, meet.into());
    assert_eq!(cast(&dnf, DVec3::new(-10.0, 0.0, 0.0), DVec3::X), None);
    assert_eq!(cast(&dnf, DVec3::new(0.0, 0.0, 10.0), -DVec3::Z), None);
}

#[test]
fn cube_faces_are_their_slabs_not_the_box() {
    let mut dag = Dag::new();
    let slabs: Vec<Edge> = [DVec3::X, DVec3::Y, DVec3::Z]
        .into_iter()
        .map(|n| {
            dag.leaf(
                Quadric::slab(DVec3::ONE, n, 1.0).unwrap(),
                Source::default(),
            )
            .into()
        })
        .collect();
    let cube = dag.intersection(slabs, Source::default());
    let cube = dag.bounded(cube, Aabb::new(DVec3::ZERO, DVec3::splat(2.0)));
    let dnf = dnf_of(&mut dag, cube.into());
    for (origin, direction) in [
        (DVec3::new(1.0, 1.0, 10.0), -DVec3::Z),
        (DVec3::new(-5.0, 0.5, 1.5), DVec3::X),
        (DVec3::new(0.3, 7.0, 0.2), -DVec3::Y),
    ] {
        let hit = cast(&dnf, origin, direction).unwrap();
        assert!(hit.quadric.is_some(), "{hit:?}");
        assert!((hit.normal + direction).length() < 1e-9, "{hit:?}");
    }
}

fn test_scene() -> Scene {
    let mut dag = Dag::new();
    let big = sphere(&mut dag, DVec3::ZERO, 2.0);
    let small = sphere(&mut dag, DVec3::new(1.0, -1.0, 1.0), 1.2);
    let tinted = dag
        .color(small, [0.2, 0.4, 0.9, 1.0], Source::default())
        .unwrap();
    let solid = dag.difference([big, tinted.into()], Source::default());
    let extra = sphere(&mut dag, DVec3::new(-2.0, 0.0, -1.0), 1.0);
    let highlighted = dag.highlight(extra, Source::default());
    let root = dag.union([solid.into(), highlighted.into()], Source::default());
    dag.set_root(root.into());
    let ghost = sphere(&mut dag, DVec3::new(0.0, 3.0, 0.0), 1.0);
    dag.add_background(ghost);
    Scene::from_dag(&mut dag, &DnfOptions::default()).unwrap()
}

#[test]
fn frames_are_identical_for_one_and_two_threads() {
    let scene = test_scene();
    let size = ImageSize::new(61, 47).unwrap();
    let camera = Camera::fit(&View::Iso, Projection::Perspective, &scene.bounds(), size).unwrap();
    let in_pool = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| render(&scene, &camera, size, &RenderOptions::default(), &|_| {}))
    };
    let one = in_pool(1);
    let two = in_pool(2);
    assert_eq!(one.rgb, two.rgb);
    assert_eq!(one.ids, two.ids);
    let bits = |f: &qcsg_render::Frame| f.depth.iter().map(|d| d.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&one), bits(&two));
    assert!(one.hit_count() > 0 && one.hit_count() < size.pixel_count());
}

#[test]
fn empty_scenes_render_the_background() {
    let mut dag = Dag::new();
    let scene = Scene::from_dag(&mut dag, &DnfOptions::default()).unwrap();
    assert!(scene.bounds().is_empty());
    let size = ImageSize::new(3, 2).unwrap();
    let camera = Camera::fit(&View::Iso, Projection::Orthographic, &scene.bounds(), size).unwrap();
    let frame = render(&scene, &camera, size, &RenderOptions::default(), &|_| {});
    assert_eq!(frame.hit_count(), 0);
    assert_eq!(frame.pixel(2, 1), [255, 255, 229]);
}

/// A plate drilled with a 10 × 10 grid of holes: one term of 103 literals, so its rays take
/// the literals whose failing part they cross from an index. Every ray must see what it sees
/// when it intersects every literal.
#[test]
fn a_term_of_many_literals_traces_as_with_every_literal() {
    let mut dag = Dag::new();
    let plate = common::drilled_plate(&mut dag, 10);
    let dnf = dnf_of(&mut dag, plate);
    assert_eq!(dnf.terms.len(), 1);
    assert!(dnf.terms[0].literals.len() > LITERAL_INDEX_ABOVE);
    let (indexed, walked) = (term_index(&dnf), TermIndex::new(&dnf, usize::MAX));
    let mut scratch = Scratch::default();
    let mut rng = Rng::new(0x5eed);
    let mut unit = || rng.unit();
    let mut hits = 0;
    for _ in 0..4000 {
        let origin = DVec3::new(
            40.0 * unit() - 20.0,
            40.0 * unit() - 20.0,
            10.0 * unit() + 2.0,
        );
        let target = DVec3::new(
            32.0 * unit() - 16.0,
            32.0 * unit() - 16.0,
            2.0 * unit() - 1.0,
        );
        let ray = Ray {
            origin,
            direction: (target - origin).normalize(),
        };
        let fast = trace(&dnf, &indexed, &ray, 0.0, &mut scratch);
        let slow = trace(&dnf, &walked, &ray, 0.0, &mut scratch);
        assert_eq!(fast, slow, "{ray:?}");
        hits += usize::from(fast.is_some());
    }
    assert!(hits > 2000, "{hits} hits");
}

/// Terms are traced front to back and those whose box lies beyond the first entry are skipped:
/// the first entry must still be found when it lies beyond a stretch of other terms, and when
/// the ray starts inside the solid, whose terms then all count (the stretch the ray starts in
/// may be extended by a term whose box it enters late).
#[test]
fn the_first_entry_is_found_past_overlapping_terms_also_from_inside() {
    // A chain of overlapping balls along x (0 to 4, centres 1.5 apart), a gap, two more.
    let mut dag = Dag::new();
    let balls: Vec<Edge> = [0.0, 1.5, 3.0, 6.0, 7.5]
        .into_iter()
        .map(|x| sphere(&mut dag, DVec3::new(x, 0.0, 0.0), 1.0))
        .collect();
    let solid = dag.union(balls, Source::default());
    let dnf = dnf_of(&mut dag, solid.into());
    assert_eq!(dnf.terms.len(), 5);
    let sixth = quadric_index(
        &dnf,
        &Quadric::sphere(DVec3::new(6.0, 0.0, 0.0), 1.0).unwrap(),
    );
    let first = quadric_index(&dnf, &Quadric::sphere(DVec3::ZERO, 1.0).unwrap());

    // From outside, on the axis, either way: the nearest ball's pole.
    let hit = cast(&dnf, DVec3::new(-3.0, 0.0, 0.0), DVec3::X).unwrap();
    assert!(
        (hit.t - 2.0).abs() < 1e-12 && hit.quadric == Some(first),
        "{hit:?}"
    );
    let hit = cast(&dnf, DVec3::new(12.0, 0.0, 0.0), -DVec3::X).unwrap();
    assert!((hit.t - 3.5).abs() < 1e-12, "{hit:?}");
    // From inside the first ball: the chain is left at x = 4, the next entry is at x = 5.
    let hit = cast(&dnf, DVec3::new(0.0, 0.0, 0.0), DVec3::X).unwrap();
    assert!(
        (hit.t - 5.0).abs() < 1e-12 && hit.quadric == Some(sixth),
        "{hit:?}"
    );
    // From inside the last ball of the chain, backwards: nothing more to enter.
    assert_eq!(cast(&dnf, DVec3::new(3.0, 0.0, 0.0), -DVec3::X), None);
    // Slanted rays from inside and outside agree with the balls' own first entry.
    for k in 0..50 {
        let angle = 0.02 * f64::from(k) - 0.5;
        let direction = DVec3::new(angle.cos(), angle.sin(), 0.3 * angle).normalize();
        for origin in [DVec3::new(-4.0, 0.1, 0.0), DVec3::new(0.2, 0.0, 0.1)] {
            let hit = cast(&dnf, origin, direction).map(|h| h.t);
            let expected = first_entry(origin, direction);
            let agree = match (hit, expected) {
                (Some(a), Some(b)) => (a - b).abs() < 1e-9,
                (a, b) => a == b,
            };
            assert!(agree, "{origin} {direction}: {hit:?}, not {expected:?}");
        }
    }
}

/// The first entry into the chain of balls of the test above, from their roots along the ray.
fn first_entry(origin: DVec3, direction: DVec3) -> Option<f64> {
    let mut pieces: Vec<(f64, f64)> = [0.0, 1.5, 3.0, 6.0, 7.5]
        .into_iter()
        .filter_map(|x| {
            let o = origin - DVec3::new(x, 0.0, 0.0);
            let (b, c) = (o.dot(direction), o.length_squared() - 1.0);
            let d = b * b - c;
            (d > 0.0).then(|| (-b - d.sqrt(), -b + d.sqrt()))
        })
        .filter(|&(_, end)| end > 0.0)
        .map(|(start, end)| (start.max(0.0), end))
        .collect();
    pieces.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut end = f64::NEG_INFINITY;
    for (start, piece_end) in pieces {
        if start > end && start > 0.0 {
            return Some(start);
        }
        end = end.max(piece_end);
    }
    None
}
