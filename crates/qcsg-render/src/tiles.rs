//! Which terms each square of a frame's pixels may see, found once per frame.
//!
//! A ray looks only at the terms whose box it crosses. Searching the R-tree of the boxes for
//! every ray was most of a frame's time for scenes of a few dozen terms; but all rays of a frame
//! come from one camera, so each box can be projected onto the image once: a box in front of
//! the eye's plane covers the rectangle spanned by its corners' projections (the projection of
//! a convex body is the hull of its vertices' projections), and only the rays through that
//! rectangle can cross it. Each square of [`TILE`] pixels lists the boxes whose rectangle,
//! grown by [`MARGIN`] pixels, reaches it; a box that reaches behind the eye's plane, or has no
//! finite corners, is listed everywhere. A ray then tests the boxes of its square exactly as it
//! tests the tree's: a list holds every box the ray crosses (and some it misses), so the terms
//! found, and the frame, are the same bit for bit.

use qcsg_csg::Aabb;
use qcsg_quadric::DVec3;

use crate::camera::{Camera, ImageSize, Projection};

/// The side of a square of pixels, in pixels.
pub const TILE: u32 = 8;

/// How far, in pixels, a box's rectangle is grown: far beyond any rounding of the rays.
const MARGIN: f64 = 2.0;

/// The most entries a frame's lists may hold (64 MiB of them).
pub const MOST_LISTED: u64 = 1 << 24;

/// For each square of [`TILE`] × [`TILE`] pixels of a frame, the boxes its rays may cross.
#[derive(Clone, Debug)]
pub struct FrameTiles {
    columns: u32,
    /// The boxes of each square, row by row: `starts[k]..starts[k + 1]` in `boxes`.
    starts: Vec<u32>,
    boxes: Vec<u32>,
}

impl FrameTiles {
    /// The squares of a `size` frame of `camera` and the `boxes` each may see; `None` when the
    /// lists would hold more than [`MOST_LISTED`] entries in all (many boxes over a large
    /// frame), where searching the tree for each ray costs less memory.
    pub fn new(boxes: &[Aabb], camera: &Camera, size: ImageSize) -> Option<Self> {
        let columns = size.width().div_ceil(TILE);
        let rows = size.height().div_ceil(TILE);
        let mut squares = Vec::with_capacity(boxes.len());
        let mut total = 0u64;
        for (index, bounds) in boxes.iter().enumerate() {
            if bounds.is_empty() {
                continue;
            }
            let (x0, x1, y0, y1) = match covered(bounds, camera, size) {
                Coverage::Nowhere => continue,
                Coverage::Everywhere => (0, size.width() - 1, 0, size.height() - 1),
                Coverage::Pixels(pixels) => pixels,
            };
            let (across, down) = (x0 / TILE..=x1 / TILE, y0 / TILE..=y1 / TILE);
            total += u64::from(x1 / TILE - x0 / TILE + 1) * u64::from(y1 / TILE - y0 / TILE + 1);
            if total > MOST_LISTED {
                return None;
            }
            squares.push((index as u32, across, down));
        }
        let mut lists = vec![Vec::new(); (columns * rows) as usize];
        for (index, across, down) in squares {
            for row in down {
                for column in across.clone() {
                    lists[(row * columns + column) as usize].push(index);
                }
            }
        }
        let mut starts = Vec::with_capacity(lists.len() + 1);
        let mut flat = Vec::with_capacity(lists.iter().map(Vec::len).sum());
        starts.push(0);
        for list in lists {
            flat.extend(list);
            starts.push(flat.len() as u32);
        }
        Some(Self {
            columns,
            starts,
            boxes: flat,
        })
    }

    /// The boxes the ray through pixel `(x, y)` may cross, ascending.
    pub fn at(&self, x: u32, y: u32) -> &[u32] {
        let k = ((y / TILE) * self.columns + x / TILE) as usize;
        match (self.starts.get(k), self.starts.get(k + 1)) {
            (Some(&start), Some(&end)) => &self.boxes[start as usize..end as usize],
            _ => &[],
        }
    }
}

/// Which pixels' rays may cross a box.
enum Coverage {
    /// None: the box projects outside the frame.
    Nowhere,
    /// Any: the projection cannot bound them (a corner not strictly in front of the eye, or
    /// not finite).
    Everywhere,
    /// Those of `(x0, x1, y0, y1)`, inclusive and within the frame.
    Pixels((u32, u32, u32, u32)),
}

/// The pixels whose rays may cross `bounds`.
fn covered(bounds: &Aabb, camera: &Camera, size: ImageSize) -> Coverage {
    let (half_height, aspect) = camera.screen_scale();
    let (width, height) = (f64::from(size.width()), f64::from(size.height()));
    let (mut left, mut right) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut top, mut bottom) = (f64::INFINITY, f64::NEG_INFINITY);
    for corner in 0..8 {
        let pick = |bit: u32, axis: usize| {
            if corner & bit == 0 {
                bounds.min[axis]
            } else {
                bounds.max[axis]
            }
        };
        let point = DVec3::new(pick(1, 0), pick(2, 1), pick(4, 2));
        let v = point - camera.eye();
        let (sx, sy) = match camera.projection() {
            Projection::Perspective => {
                let depth = v.dot(camera.forward());
                // Near the eye's plane the projection runs off: every pixel, to be safe.
                let in_front = depth > 1e-6 * v.length();
                if !in_front {
                    return Coverage::Everywhere;
                }
                (v.dot(camera.right()) / depth, v.dot(camera.up()) / depth)
            }
            Projection::Orthographic => (v.dot(camera.right()), v.dot(camera.up())),
        };
        // The pixel coordinates (centres at half-integers, as `Camera::ray` takes them).
        let x = (sx / (half_height * aspect) + 1.0) * 0.5 * width;
        let y = (1.0 - sy / half_height) * 0.5 * height;
        if !(x.is_finite() && y.is_finite()) {
            return Coverage::Everywhere;
        }
        left = left.min(x);
        right = right.max(x);
        top = top.min(y);
        bottom = bottom.max(y);
    }
    if left - MARGIN > width
        || right + MARGIN < 0.0
        || top - MARGIN > height
        || bottom + MARGIN < 0.0
    {
        return Coverage::Nowhere;
    }
    // Pixel `i` has its centre at `i + 0.5`: the pixels whose centres lie in the grown range.
    let first = |from: f64, limit: f64| (from - MARGIN - 0.5).floor().clamp(0.0, limit - 1.0);
    let last = |to: f64, limit: f64| (to + MARGIN - 0.5).ceil().clamp(0.0, limit - 1.0);
    Coverage::Pixels((
        first(left, width) as u32,
        last(right, width) as u32,
        first(top, height) as u32,
        last(bottom, height) as u32,
    ))
}
