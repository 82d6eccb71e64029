//! The ray tracer's shortcuts change no pixel: a frame rendered with them (the quadrics' values
//! at the eye computed once per perspective frame, the terms of a few literals read only where
//! their literals may fail, a term left as soon as it cannot begin before the nearest entry
//! found) holds, bit for bit, the depth and ids that tracing each pixel's ray without any of
//! them gives, in both projections and from inside the solid. So do the boxes of where each
//! term may hold (smaller than its box for the cells of a polygon) and the literals each square
//! of pixels lists for its terms.

#[path = "common/mod.rs"]
mod common;

use qcsg_csg::{Aabb, Dag, DnfOptions, Edge, Source};
use qcsg_quadric::{DVec3, Quadric};
use qcsg_render::raytrace::{Scratch, TermIndex};
use qcsg_render::tiles::{FrameTiles, TermBoxes};
use qcsg_render::{Camera, ImageSize, Projection, RenderOptions, Scene, View, render, trace};

fn sphere(dag: &mut Dag, centre: DVec3, radius: f64) -> Edge {
    let r = DVec3::splat(radius);
    dag.bounded_leaf(
        Quadric::sphere(centre, radius).unwrap(),
        Source::default(),
        Aabb::new(centre - r, centre + r),
    )
    .into()
}

/// A plate drilled with 4 × 4 holes (one term of 19 literals: a few, read where they fail),
/// with overlapping balls on it and through it (terms in front of and behind each other).
fn scene() -> Scene {
    let mut dag = Dag::new();
    let mut parts = vec![common::drilled_plate(&mut dag, 4)];
    for (i, x) in [-2.5, -0.5, 1.5].into_iter().enumerate() {
        parts.push(sphere(
            &mut dag,
            DVec3::new(x, 0.3 * i as f64, 0.8),
            1.2 + 0.1 * i as f64,
        ));
    }
    parts.push(sphere(&mut dag, DVec3::new(1.5, 1.5, 0.0), 1.0));
    let root = dag.union(parts, Source::default());
    dag.set_root(root.into());
    Scene::from_dag(&mut dag, &DnfOptions::default()).unwrap()
}

/// Renders through `camera` and compares every pixel with its ray traced plainly.
fn compare(scene: &Scene, camera: &Camera, size: ImageSize) -> usize {
    let frame = render(scene, camera, size, &RenderOptions::default(), &|_| {});
    let layer = scene.solid.as_ref().unwrap();
    let plain = TermIndex::plain(layer.dnf());
    let mut scratch = Scratch::default();
    let mut hits = 0;
    for y in 0..size.height() {
        for x in 0..size.width() {
            let ray = camera.ray(f64::from(x) + 0.5, f64::from(y) + 0.5, size);
            let hit = trace(layer.dnf(), &plain, &ray, 0.0, &mut scratch);
            let i = frame.index(x, y);
            let depth = hit.map_or(f64::INFINITY, |h| h.t);
            assert_eq!(
                frame.depth[i].to_bits(),
                depth.to_bits(),
                "depth at ({x}, {y})"
            );
            assert_eq!(
                frame.ids[i].quadric,
                hit.and_then(|h| h.quadric).unwrap_or(u32::MAX),
                "quadric at ({x}, {y})"
            );
            hits += usize::from(hit.is_some());
        }
    }
    hits
}

#[test]
fn frames_hold_the_plainly_traced_pixels() {
    let scene = scene();
    let few = scene
        .solid
        .as_ref()
        .unwrap()
        .dnf()
        .terms
        .iter()
        .any(|t| (17..=32).contains(&t.literals.len()));
    assert!(few, "the scene has a term of a few literals");
    let size = ImageSize::new(64, 48).unwrap();
    let bounds = scene.bounds();
    let mut hits = 0;
    for projection in [Projection::Perspective, Projection::Orthographic] {
        for view in [View::Iso, View::Top, View::Front] {
            let camera = Camera::fit(&view, projection, &bounds, size).unwrap();
            let seen = compare(&scene, &camera, size);
            assert!(seen > 0, "{view:?} {projection:?}");
            hits += seen;
        }
    }
    assert!(hits > 2000, "{hits} pixels show the solid");
    // From inside a ball and inside the plate: intervals begin at the ray's start.
    for eye in [DVec3::new(-2.5, 0.0, 0.8), DVec3::new(0.0, -0.2, 0.0)] {
        let view = View::Explicit {
            eye,
            center: DVec3::new(3.0, 2.0, -1.0),
        };
        let camera = Camera::fit(&view, Projection::Perspective, &bounds, size).unwrap();
        compare(&scene, &camera, size);
    }
}

/// A grid of small balls: many terms, each seen by a few pixels.
fn balls() -> Scene {
    let mut dag = Dag::new();
    let mut parts = Vec::new();
    for i in 0..8 {
        for j in 0..6 {
            let centre = DVec3::new(
                f64::from(i) - 3.5,
                f64::from(j) - 2.5,
                0.3 * f64::from(i % 3),
            );
            parts.push(sphere(&mut dag, centre, 0.3 + 0.02 * f64::from(j)));
        }
    }
    let root = dag.union(parts, Source::default());
    dag.set_root(root.into());
    Scene::from_dag(&mut dag, &DnfOptions::default()).unwrap()
}

/// Every term whose box a pixel's ray crosses (beyond its start) is among those the frame's
/// square of that pixel lists, for cameras whose frame cuts boxes, and whose eye is among them
/// or between them; and such frames hold the plainly traced pixels.
#[test]
fn squares_of_pixels_list_every_box_their_rays_cross() {
    let scene = balls();
    let layer = scene.solid.as_ref().unwrap();
    let boxes = layer.index().boxes();
    // Not a whole number of squares, so that the last row and column are partial.
    let size = ImageSize::new(61, 45).unwrap();
    let views = [
        View::Iso,
        View::Top,
        View::Explicit {
            eye: DVec3::new(-1.0, -4.0, 1.5),
            center: DVec3::new(1.0, 1.0, 0.0),
        },
        // Among the balls: some boxes lie behind the eye, some around it.
        View::Explicit {
            eye: DVec3::new(0.0, 0.0, 0.2),
            center: DVec3::new(3.0, 2.0, 0.2),
        },
        View::Explicit {
            eye: DVec3::new(-0.5, -0.5, 0.0),
            center: DVec3::new(-0.5, 3.0, 0.0),
        },
    ];
    let mut listed = 0usize;
    for projection in [Projection::Perspective, Projection::Orthographic] {
        for view in &views {
            let camera = Camera::fit(view, projection, &scene.bounds(), size).unwrap();
            let tiles = FrameTiles::new(boxes, &camera, size).unwrap();
            for y in 0..size.height() {
                for x in 0..size.width() {
                    let ray = camera.ray(f64::from(x) + 0.5, f64::from(y) + 0.5, size);
                    let list = tiles.at(x, y);
                    listed += list.len();
                    for (k, b) in boxes.iter().enumerate() {
                        let crosses = ray
                            .clip_to(b)
                            .is_some_and(|(t_in, t_out)| t_in.max(0.0) < t_out);
                        assert!(
                            !crosses || list.contains(&(k as u32)),
                            "{view:?} {projection:?}: pixel ({x}, {y}) crosses box {k}, unlisted"
                        );
                    }
                }
            }
            compare(&scene, &camera, size);
        }
    }
    // The lists are not every box everywhere (which would pass the test above trivially).
    let pixels = 10 * size.pixel_count();
    assert!(
        listed < pixels * boxes.len() / 4,
        "{listed} listed for {pixels} pixels and {} boxes",
        boxes.len()
    );
}

/// Lists that would grow too long (boxes over all of a large frame) are not made: the frame's
/// rays search the tree instead.
#[test]
fn squares_of_pixels_give_way_to_the_tree_for_too_many_boxes() {
    let size = ImageSize::new(4096, 4096).unwrap();
    let bounds = Aabb::new(DVec3::splat(-1.0), DVec3::splat(1.0));
    let camera = Camera::fit(&View::Iso, Projection::Perspective, &bounds, size).unwrap();
    let squares = u64::from(size.width().div_ceil(qcsg_render::tiles::TILE)).pow(2);
    let fits = (qcsg_render::tiles::MOST_LISTED / squares) as usize;
    // Around the eye: seen by every pixel.
    let around = Aabb::new(DVec3::splat(-1e3), DVec3::splat(1e3));
    let over_all = |count: usize| vec![around; count];
    assert!(FrameTiles::new(&over_all(fits), &camera, size).is_some());
    assert!(FrameTiles::new(&over_all(fits + 1), &camera, size).is_none());
}

/// A plate cut by a hexagon, two triangles and round holes, extruded (as
/// `examples/laser_cut_plate.scad`): the polygons' cells are terms of a few literals whose
/// boxes are much larger than the cells.
fn polygon_plate() -> Scene {
    let text = "linear_extrude(height = 3) difference() {
        square([40, 24], center = true);
        polygon([for (a = [0 : 60 : 300]) 6 * [cos(a), sin(a)]]);
        for (m = [0, 1]) mirror([m, 0]) translate([12, 0]) polygon([[-3, -5], [4, 0], [-3, 5]]);
        for (x = [-16, 16], y = [-8, 8]) translate([x, y]) circle(d = 3);
    }";
    let options = qcsg_driver::Options::from_env(Vec::new());
    let compilation = qcsg_driver::compile(
        "plate.scad",
        text.to_owned(),
        &options,
        &qcsg_sema::FsLoader,
        qcsg_driver::Stage::Dnf,
    );
    assert!(!compilation.analysis.has_errors());
    Scene::from_layers(compilation.layers.unwrap())
}

#[test]
fn polygon_cells_hold_the_plainly_traced_pixels() {
    let scene = polygon_plate();
    let layer = scene.solid.as_ref().unwrap();
    let index = layer.index();
    // Some terms hold in a box smaller than theirs, and some keep literal boxes: the
    // comparisons below exercise both.
    let volume = |b: &Aabb| (b.max - b.min).element_product();
    let smaller = index
        .boxes()
        .iter()
        .zip(index.square_boxes())
        .filter(|(own, holds)| volume(holds) < 0.5 * volume(own))
        .count();
    assert!(smaller >= 4, "{smaller} terms hold in a smaller box");
    let size = ImageSize::new(64, 48).unwrap();
    let bounds = scene.bounds();
    let mut hits = 0;
    let mut listed = false;
    let views = [
        View::Iso,
        View::Top,
        View::Explicit {
            eye: DVec3::new(30.0, -40.0, 12.0),
            center: DVec3::new(2.0, 1.0, 1.5),
        },
        // Within the plate's thickness, along it: rays graze the cells' faces.
        View::Explicit {
            eye: DVec3::new(-60.0, 3.0, 1.5),
            center: DVec3::new(0.0, 0.0, 1.5),
        },
    ];
    for projection in [Projection::Perspective, Projection::Orthographic] {
        for view in &views {
            let camera = Camera::fit(view, projection, &bounds, size).unwrap();
            let tiles = FrameTiles::with_literals(index, &camera, size).unwrap();
            listed |= (0..size.height()).step_by(8).any(|y| {
                (0..size.width()).step_by(8).any(|x| {
                    let square = tiles.square(x, y);
                    (0..square.boxes.len()).any(|k| square.literals(k).is_some())
                })
            });
            hits += compare(&scene, &camera, size);
        }
    }
    assert!(listed, "no square lists the literals of its terms");
    assert!(hits > 3000, "{hits} pixels show the solid");
}
