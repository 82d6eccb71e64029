//! Layer 1: the basic regions of the three sampling planes cover every quadric kind inside a box,
//! and each covered point is reached by a region where its distortion is at most √3 and that
//! owns it (a border region's subdivision drops the parts another plane is best on).

mod common;

use common::{Rng, points_on};
use qcsg_csg::Aabb;
use qcsg_quadric::{DMat4, DVec3, HeightfieldForm, PrincipalFrame, Quadric, QuadricKind};
use qcsg_sample::regions::{
    BasicRegion, Held, Owned, REGION_SAMPLES, Rect, RegionCap, RegionStats, SmallPatches,
    basic_regions, basic_regions_within, patch_bounds, region_point,
};

fn kinds() -> Vec<(&'static str, Quadric)> {
    let rotation = DMat4::from_axis_angle(DVec3::new(0.3, -0.7, 0.5).normalize(), 0.9)
        * DMat4::from_translation(DVec3::new(0.1, -0.2, 0.15));
    let base = [
        ("sphere", Quadric::sphere(DVec3::ZERO, 1.2)),
        (
            "ellipsoid",
            Quadric::ellipsoid(DVec3::ZERO, DVec3::new(1.5, 0.7, 0.3)),
        ),
        ("cylinder", Quadric::cylinder(DVec3::ZERO, DVec3::Z, 0.8)),
        (
            "elliptic cylinder",
            Quadric::elliptic_cylinder(DVec3::ZERO, 1, (0.9, 0.3)),
        ),
        ("cone", Quadric::cone(DVec3::ZERO, DVec3::Z, 0.7)),
        ("narrow cone", Quadric::cone(DVec3::ZERO, DVec3::Z, 0.2)),
        (
            "paraboloid",
            Quadric::paraboloid(DVec3::new(0.0, 0.0, -1.0), DVec3::Z, 0.3),
        ),
        (
            "hyperboloid 1",
            Quadric::hyperboloid_one_sheet(DVec3::ZERO, DVec3::Z, 0.6, 0.8),
        ),
        (
            "hyperboloid 2",
            Quadric::hyperboloid_two_sheets(DVec3::ZERO, DVec3::Z, 0.6, 0.4),
        ),
        (
            "plane",
            Quadric::half_space(DVec3::new(0.1, 0.2, 0.3), DVec3::new(1.0, 2.0, 0.5)),
        ),
        (
            "slab",
            Quadric::slab(DVec3::ZERO, DVec3::new(0.2, 1.0, 0.1), 0.7),
        ),
    ];
    let mut out = Vec::new();
    for (name, q) in base {
        let q = q.expect("quadric");
        out.push((name, q));
        out.push((name, q.transformed(&rotation).expect("transform")));
    }
    out
}

/// The basic regions of all three sampling planes of `q` inside `bounds`, with its frame and the
/// decomposition's counters.
fn regions_of(q: &Quadric, bounds: &Aabb) -> (PrincipalFrame, Vec<BasicRegion>, RegionStats) {
    let frame = q.frame();
    let mut regions = Vec::new();
    let mut stats = RegionStats::default();
    for hf in frame.heightfields() {
        basic_regions(&frame, &hf, bounds, (0, 0), &mut regions, &mut stats);
    }
    (frame, regions, stats)
}

/// Whether some region that owns `p` maps to it with distortion at most √3 there.
fn reached(frame: &PrincipalFrame, regions: &[BasicRegion], p: DVec3, scale: f64) -> bool {
    let f = frame.to_frame(p).to_array();
    regions.iter().any(|r| {
        let hf = &r.heightfield;
        let (i, j) = hf.plane_axes;
        let (x, y, t) = (f[i], f[j], f[hf.normal_axis]);
        let point = Rect {
            x: (x, x),
            y: (y, y),
        };
        if !r.rect.contains(x, y) || r.owns_none_of(&point) {
            return false;
        }
        let Some(h) = hf.height(x, y) else {
            return false;
        };
        let mapped = frame.heightfield_point(hf, x, y, r.sheet * h);
        let on_it = (mapped - p).length() <= 1e-7 * scale
            || (matches!(hf.form, HeightfieldForm::Root { .. })
                && (r.sheet * h - t).abs() <= 1e-7 * scale);
        let low = hf
            .distortion(x, y)
            .is_some_and(|d| d <= 3f64.sqrt() * (1.0 + 1e-9));
        on_it
            && low
            && r.max_distortion >= hf.distortion(x, y).unwrap_or(f64::INFINITY) * (1.0 - 1e-9)
    })
}

#[test]
fn regions_cover_every_kind_inside_the_box() {
    let bounds = Aabb::new(DVec3::new(-1.6, -1.3, -1.1), DVec3::new(1.4, 1.5, 1.2));
    let mut rng = Rng::new(7);
    for (name, q) in kinds() {
        assert!(
            !matches!(q.kind(), QuadricKind::Empty | QuadricKind::AllSpace),
            "{name}"
        );
        let (frame, regions, stats) = regions_of(&q, &bounds);
        assert!(!regions.is_empty(), "{name}: no regions");
        let points = points_on(&q, &bounds, 400, &mut rng);
        assert!(points.len() >= 100, "{name}: too few test points");
        let missed: Vec<_> = points
            .iter()
            .filter(|&&p| !reached(&frame, &regions, p, 3.0))
            .collect();
        assert!(
            missed.is_empty(),
            "{name} ({:?}): {} of {} points not covered, e.g. {:?}; {} regions, {:?}",
            q.kind(),
            missed.len(),
            points.len(),
            missed.first(),
            regions.len(),
            stats
        );
    }
}

/// A border region's ownership agrees with its plane point by point: over a rectangle it owns
/// all of, its plane is the best (the normal's largest component is along the plane's normal) at
/// every surface point of a grid, and over one it owns none of, at none.
#[test]
fn ownership_agrees_with_the_normals() {
    let bounds = Aabb::new(DVec3::new(-1.6, -1.3, -1.1), DVec3::new(1.4, 1.5, 1.2));
    let (mut decided, mut points) = (0, 0);
    for (name, q) in kinds() {
        let (frame, regions, _) = regions_of(&q, &bounds);
        for region in regions.iter().filter(|r| r.border.is_some()) {
            let hf = &region.heightfield;
            let (i, j) = hf.plane_axes;
            let rect = region.rect;
            let at = |(a, b): (f64, f64), k: f64| a + (b - a) * k;
            for (kx, ky) in (0..4).flat_map(|kx| (0..4).map(move |ky| (kx, ky))) {
                let part = Rect {
                    x: (
                        at(rect.x, kx as f64 / 4.0),
                        at(rect.x, (kx + 1) as f64 / 4.0),
                    ),
                    y: (
                        at(rect.y, ky as f64 / 4.0),
                        at(rect.y, (ky + 1) as f64 / 4.0),
                    ),
                };
                let owned = region.owns(&part);
                if owned == Owned::Part {
                    continue;
                }
                decided += 1;
                for (gx, gy) in (0..=4).flat_map(|gx| (0..=4).map(move |gy| (gx, gy))) {
                    let (x, y) = (at(part.x, gx as f64 / 4.0), at(part.y, gy as f64 / 4.0));
                    let Some(h) = hf.height(x, y) else {
                        continue;
                    };
                    let p = frame.heightfield_point(hf, x, y, region.sheet * h);
                    let Some(n) = q.normal(p) else {
                        continue;
                    };
                    let along = |k: usize| n.dot(frame.axes[k]).abs();
                    let margin = along(hf.normal_axis) - along(i).max(along(j));
                    points += 1;
                    match owned {
                        Owned::All => assert!(
                            margin >= -1e-9,
                            "{name}: {part:?} owned, but another plane is better at ({x}, {y})"
                        ),
                        _ => assert!(
                            margin <= 1e-9,
                            "{name}: {part:?} not owned, but its plane is best at ({x}, {y})"
                        ),
                    }
                }
            }
        }
    }
    assert!(
        decided > 100 && points > 1000,
        "{decided} rectangles, {points} points"
    );
}

#[test]
fn degenerate_kinds_use_the_expected_planes() {
    let bounds = Aabb::new(DVec3::splat(-1.0), DVec3::splat(1.0));
    let count = |q: Quadric| {
        let frame = q.frame();
        let mut planes = [0usize; 3];
        let mut stats = RegionStats::default();
        for hf in frame.heightfields() {
            let mut regions = Vec::new();
            basic_regions(&frame, &hf, &bounds, (0, 0), &mut regions, &mut stats);
            planes[hf.normal_axis] = regions.len();
        }
        planes.iter().filter(|&&n| n > 0).count()
    };
    // A plane: one sampling plane (its own), a polygon of rectangles.
    let plane = Quadric::half_space(DVec3::ZERO, DVec3::new(1.0, 1.0, 0.3)).unwrap();
    assert_eq!(count(plane), 1);
    // A slab: one plane, both sheets.
    let slab = Quadric::slab(DVec3::ZERO, DVec3::Z, 0.5).unwrap();
    assert_eq!(count(slab), 1);
    // A cylinder: the two planes containing the axis.
    let cylinder = Quadric::cylinder(DVec3::ZERO, DVec3::new(1.0, 0.2, 0.0), 0.5).unwrap();
    assert_eq!(count(cylinder), 2);
}

/// The box of each region's patch holds every surface point over the region (eq. 22 of a region
/// keeps only the terms near that box, so a point outside it could be misclassified).
#[test]
fn patch_bounds_hold_the_patch() {
    let bounds = Aabb::new(DVec3::new(-1.6, -1.3, -1.1), DVec3::new(1.4, 1.5, 1.2));
    let mut rng = Rng::new(11);
    for (name, q) in kinds() {
        let (frame, regions, _) = regions_of(&q, &bounds);
        for region in &regions {
            let patch = patch_bounds(&frame, region).expect("a heightfield");
            for _ in 0..20 {
                let (x, y) = (
                    rng.range(region.rect.x.0, region.rect.x.1),
                    rng.range(region.rect.y.0, region.rect.y.1),
                );
                let Some(p) = region_point(&frame, &region.heightfield, region.sheet, x, y) else {
                    continue;
                };
                assert!(
                    (patch.min.cmple(p) & p.cmple(patch.max)).all(),
                    "{name}: {p} over {:?} outside {patch:?}",
                    region.rect
                );
            }
        }
    }
}

/// A cap on the regions kept, [`REGION_SAMPLES`] samples each, stops the partition as soon as it
/// is crossed and names the quadric; under the cap the regions are those of an uncapped
/// partition.
#[test]
fn the_region_cap_stops_the_partition() {
    let q = Quadric::sphere(DVec3::ZERO, 1.0).expect("a sphere");
    let bounds = Aabb::new(DVec3::splat(-1.0), DVec3::splat(1.0));
    let (_, all, _) = regions_of(&q, &bounds);
    let frame = q.frame();
    let partition = |limit: u64| {
        let cap = RegionCap::new(limit);
        let mut regions = Vec::new();
        let mut stats = RegionStats::default();
        for hf in frame.heightfields() {
            let key = (7, 0);
            let out = (&mut regions, &cap);
            basic_regions_within(
                &frame,
                &hf,
                (&bounds, SmallPatches::NONE),
                key,
                out,
                &mut stats,
            );
        }
        (regions, cap.crossed())
    };
    // Each region is charged as the samples that take as much memory.
    let count = all.len() as u64;
    let held = count * REGION_SAMPLES;
    let (under, crossed) = partition(held);
    assert_eq!(crossed, None);
    assert_eq!(under.len(), all.len());
    let (over, crossed) = partition(held - 1);
    assert_eq!(crossed, Some((7, Held::Regions)));
    assert!((over.len() as u64) < count, "{} regions", over.len());
}
