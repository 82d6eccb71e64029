//! Differences and intersections with parts made of many plane cells (polygons, meshes) stay
//! near-linear in the DNF: the part is cut into convex cells of itself or of its complement
//! instead of multiplying out the cells' complements.

use qcsg_csg::{Aabb, Dag, DnfOptions, Edge, Source, build_dnf};
use qcsg_quadric::{DVec3, Quadric};

/// A z-invariant column over the axis-parallel rectangle `[lo, hi]` turned by `angle` about its
/// centre, as a polygon's cell is built: four half-spaces, a declared box unbounded in z.
fn column(dag: &mut Dag, lo: (f64, f64), hi: (f64, f64), angle: f64) -> Edge {
    let at = Source::default();
    let centre = DVec3::new(0.5 * (lo.0 + hi.0), 0.5 * (lo.1 + hi.1), 0.0);
    let half = [0.5 * (hi.0 - lo.0), 0.5 * (hi.1 - lo.1)];
    let (s, c) = angle.sin_cos();
    let axes = [DVec3::new(c, s, 0.0), DVec3::new(-s, c, 0.0)];
    let mut sides = Vec::new();
    for (axis, h) in axes.iter().zip(half) {
        for sign in [1.0, -1.0] {
            let normal = *axis * sign;
            let q = Quadric::half_space(centre + normal * h, normal).unwrap();
            sides.push(dag.leaf(q, at).into());
        }
    }
    let cell = dag.intersection(sides, at);
    let reach = half[0].hypot(half[1]);
    let bounds = Aabb::new(
        DVec3::new(centre.x - reach, centre.y - reach, f64::NEG_INFINITY),
        DVec3::new(centre.x + reach, centre.y + reach, f64::INFINITY),
    );
    dag.bounded(cell, bounds).into()
}

/// The box `[lo, hi]` as three slabs.
fn cube(dag: &mut Dag, lo: DVec3, hi: DVec3) -> Edge {
    let at = Source::default();
    let centre = 0.5 * (lo + hi);
    let slabs: Vec<Edge> = [DVec3::X, DVec3::Y, DVec3::Z]
        .into_iter()
        .map(|n| {
            let half = n.dot(hi - lo) * 0.5;
            dag.leaf(Quadric::slab(centre, n, half).unwrap(), at).into()
        })
        .collect();
    let node = dag.intersection(slabs, at);
    dag.bounded(node, Aabb::new(lo, hi)).into()
}

/// `k` tilted squares in a row, each in its own unit of x.
fn row(dag: &mut Dag, k: usize, y: f64, angle: f64) -> Edge {
    let cells: Vec<Edge> = (0..k)
        .map(|i| {
            let x = i as f64 + 1.0;
            column(dag, (x + 0.2, y + 0.2), (x + 0.8, y + 0.8), angle)
        })
        .collect();
    dag.union(cells, Source::default()).into()
}

/// A deterministic point in the box.
fn points(bounds: &Aabb, count: usize) -> impl Iterator<Item = DVec3> + '_ {
    let mut state = 0x2545_f491_4f6c_dd1du64;
    (0..count).map(move |_| {
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        bounds.min + (bounds.max - bounds.min) * DVec3::new(next(), next(), next())
    })
}

/// The DNF's term count for a plate minus `k` squares, checked against the DAG at many points.
fn plate_minus_squares(k: usize) -> usize {
    let mut dag = Dag::new();
    let plate = cube(&mut dag, DVec3::ZERO, DVec3::new(k as f64 + 2.0, 2.0, 1.0));
    let holes = row(&mut dag, k, 0.5, 0.3);
    let solid = dag.difference([plate, holes], Source::default());
    dag.set_root(solid.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    assert!(dnf.stats.construction.plane_parts >= 1);
    let bounds = Aabb::new(DVec3::splat(-0.5), DVec3::new(k as f64 + 2.5, 2.5, 1.5));
    for p in points(&bounds, 20_000) {
        assert_eq!(dnf.contains(p), dag.contains(p), "{p}");
    }
    dnf.terms.len()
}

#[test]
fn a_plate_minus_many_cells_grows_linearly() {
    // The plain expansion of the difference is the product of the squares' complements (4^k
    // terms before pruning); the cells of the complement grow with k.
    let counts: Vec<usize> = [25, 50, 100, 200]
        .into_iter()
        .map(plate_minus_squares)
        .collect();
    for (k, &terms) in [25, 50, 100, 200].iter().zip(&counts) {
        assert!(terms <= 12 * k, "{k} squares: {terms} terms");
    }
    for pair in counts.windows(2) {
        // Doubling the squares at most about doubles the terms.
        assert!(
            pair[1] <= 2 * pair[0] + 16,
            "{counts:?} grows faster than linearly"
        );
    }
}

#[test]
fn two_rows_of_cells_intersect_cell_by_cell() {
    let counts: Vec<usize> = [50, 100, 200]
        .into_iter()
        .map(|k| {
            let mut dag = Dag::new();
            let a = row(&mut dag, k, 0.0, 0.0);
            let b = row(&mut dag, k, 0.3, 0.5);
            let both = dag.intersection([a, b], Source::default());
            let slab = cube(
                &mut dag,
                DVec3::new(-1.0, -1.0, 0.0),
                DVec3::new(k as f64 + 3.0, 3.0, 1.0),
            );
            let solid = dag.intersection([both.into(), slab], Source::default());
            dag.set_root(solid.into());
            let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
            let bounds = Aabb::new(DVec3::splat(-0.5), DVec3::new(k as f64 + 2.5, 2.0, 1.5));
            for p in points(&bounds, 10_000) {
                assert_eq!(dnf.contains(p), dag.contains(p), "{p}");
            }
            dnf.terms.len()
        })
        .collect();
    assert!(counts[2] <= 2 * counts[1] + 16 && counts[1] <= 2 * counts[0] + 16);
    assert!(counts[2] <= 8 * 200, "{counts:?}");
}

#[test]
fn the_limit_still_holds() {
    let mut dag = Dag::new();
    let plate = cube(&mut dag, DVec3::ZERO, DVec3::new(202.0, 2.0, 1.0));
    let holes = row(&mut dag, 200, 0.5, 0.3);
    let solid = dag.difference([plate, holes], Source::default());
    dag.set_root(solid.into());
    let options = DnfOptions {
        term_limit: 100,
        ..DnfOptions::default()
    };
    let errors = build_dnf(&dag, &options).unwrap_err();
    assert_eq!(errors[0].code, qcsg_csg::codes::TERM_LIMIT);
}
