//! Which terms each square of a frame's pixels may see, and which of their literals, found once
//! per frame.
//!
//! A ray looks only at the terms whose box it crosses. Searching the R-tree of the boxes for
//! every ray was most of a frame's time for scenes of a few dozen terms; but all rays of a frame
//! come from one camera, so each box can be projected onto the image once: a box in front of
//! the eye's plane projects into the convex hull of its corners' projections (the projection of
//! a convex body is the hull of its vertices' projections), and only the rays through that
//! outline can cross it. Each square of [`TILE`] pixels lists the boxes whose outline, grown by
//! [`MARGIN`] pixels, reaches it (the outline of a thin box seen obliquely is a thin slanted
//! band, far smaller than its rectangle); a box that reaches behind the eye's plane, or has no
//! finite corners, is listed everywhere. A ray then tests the boxes of its square exactly as it
//! tests the tree's: a list holds every box the ray crosses (and some it misses), so the terms
//! found, and the frame, are the same bit for bit.
//!
//! The boxes projected are those of where each term may hold ([`TermBoxes::square_boxes`]),
//! and for a term that keeps a box around where each of its literals may fail, the square also
//! lists the literals whose box reaches it: along the square's rays the others hold throughout
//! the term's box, so a ray reads only the listed ones, without testing every literal box.

use qcsg_csg::Aabb;
use qcsg_quadric::DVec3;

use crate::camera::{Camera, ImageSize, Projection};

/// The side of a square of pixels, in pixels.
pub const TILE: u32 = 8;

/// How far, in pixels, a box's rectangle is grown: far beyond any rounding of the rays.
const MARGIN: f64 = 2.0;

/// The most entries a frame's lists may hold (64 MiB of them).
pub const MOST_LISTED: u64 = 1 << 24;

/// For each square of [`TILE`] × [`TILE`] pixels of a frame, the boxes its rays may cross and,
/// for a term whose index keeps where each literal may fail, the literals that may fail where
/// those rays go.
#[derive(Clone, Debug)]
pub struct FrameTiles {
    columns: u32,
    /// The boxes of each square, row by row: `starts[k]..starts[k + 1]` in `boxes`.
    starts: Vec<u32>,
    boxes: Vec<u32>,
    /// For each entry of `boxes`, its literals in `literals` ([`NOT_LISTED`] where the square
    /// lists none for it: the term keeps no literal boxes, or the lists grew too long).
    literal_ranges: Vec<(u32, u32)>,
    /// DNF quadric ids, ascending within each range.
    literals: Vec<u32>,
}

/// The range of a square's entry whose literals are not listed.
const NOT_LISTED: (u32, u32) = (u32::MAX, u32::MAX);

/// What one square of pixels lists: the boxes its rays may cross, and for some of them the
/// literals that may fail along those rays.
#[derive(Clone, Copy, Debug)]
pub struct Square<'a> {
    /// Positions in the term index's boxes, ascending.
    pub boxes: &'a [u32],
    ranges: &'a [(u32, u32)],
    literals: &'a [u32],
}

impl<'a> Square<'a> {
    /// The literals (DNF quadric ids, ascending) of the term of `boxes[k]` that may fail along
    /// this square's rays within the term's box: every other literal holds along them there,
    /// as the term's literal boxes show. `None` when the square does not list them.
    pub fn literals(&self, k: usize) -> Option<&'a [u32]> {
        match self.ranges.get(k) {
            Some(&(start, end)) if (start, end) != NOT_LISTED => {
                self.literals.get(start as usize..end as usize)
            }
            _ => None,
        }
    }
}

/// What a frame's squares are made from: per term a box that every ray reaching the term
/// crosses and, for the terms that keep them, where each literal may fail (boxes in the term's
/// literal order) and the literals' ids.
pub trait TermBoxes {
    /// Per term, a box outside which rays find nothing of it.
    fn square_boxes(&self) -> &[Aabb];
    /// Where each literal of the term `term` may fail, with the literal's DNF quadric id;
    /// `None` for a term that keeps no such boxes.
    fn literal_boxes(&self, term: usize) -> Option<(&[Aabb], &[u32])>;
}

impl FrameTiles {
    /// The squares of a `size` frame of `camera` and the `boxes` each may see; `None` when the
    /// lists would hold more than [`MOST_LISTED`] entries in all (many boxes over a large
    /// frame), where searching the tree for each ray costs less memory.
    pub fn new(boxes: &[Aabb], camera: &Camera, size: ImageSize) -> Option<Self> {
        let (columns, starts, boxes) = square_lists(boxes, camera, size)?;
        let literal_ranges = vec![NOT_LISTED; boxes.len()];
        Some(Self {
            columns,
            starts,
            boxes,
            literal_ranges,
            literals: Vec::new(),
        })
    }

    /// [`FrameTiles::new`] for the boxes of `terms`, with the literals of each square's terms
    /// that may fail where its rays go: those whose literal box projects, grown by [`MARGIN`]
    /// pixels, onto the square (every literal box a ray's piece in the term's box meets is
    /// among them). Literals are left unlisted (the rays select them) where the lists would
    /// hold more than [`MOST_LISTED`] entries.
    pub fn with_literals(terms: &impl TermBoxes, camera: &Camera, size: ImageSize) -> Option<Self> {
        let mut tiles = Self::new(terms.square_boxes(), camera, size)?;
        // The squares each literal box reaches, per term, computed once per term.
        let mut reach: Vec<Option<Vec<Option<SquareRange>>>> =
            vec![None; terms.square_boxes().len()];
        let rows = (tiles.starts.len() - 1) as u32 / tiles.columns.max(1);
        for (term, slot) in reach.iter_mut().enumerate() {
            if let Some((boxes, _)) = terms.literal_boxes(term) {
                let squares = boxes
                    .iter()
                    .map(|b| square_range(b, camera, size, tiles.columns, rows))
                    .collect();
                *slot = Some(squares);
            }
        }
        let mut total = 0u64;
        for square in 0..tiles.starts.len() - 1 {
            let (row, column) = (square as u32 / tiles.columns, square as u32 % tiles.columns);
            let entries = tiles.starts[square] as usize..tiles.starts[square + 1] as usize;
            for entry in entries {
                let term = tiles.boxes[entry] as usize;
                let (Some(Some(squares)), Some((_, ids))) =
                    (reach.get(term), terms.literal_boxes(term))
                else {
                    continue;
                };
                let start = tiles.literals.len();
                tiles.literals.extend(
                    squares
                        .iter()
                        .zip(ids)
                        .filter(|(range, _)| range.is_some_and(|r| r.holds(column, row)))
                        .map(|(_, &id)| id),
                );
                total += (tiles.literals.len() - start) as u64;
                if total > MOST_LISTED {
                    tiles.literals = Vec::new();
                    tiles.literal_ranges.fill(NOT_LISTED);
                    return Some(tiles);
                }
                tiles.literal_ranges[entry] = (start as u32, tiles.literals.len() as u32);
            }
        }
        Some(tiles)
    }

    /// The boxes the ray through pixel `(x, y)` may cross, ascending.
    pub fn at(&self, x: u32, y: u32) -> &[u32] {
        self.square(x, y).boxes
    }

    /// What the square of pixel `(x, y)` lists.
    pub fn square(&self, x: u32, y: u32) -> Square<'_> {
        let k = ((y / TILE) * self.columns + x / TILE) as usize;
        match (self.starts.get(k), self.starts.get(k + 1)) {
            (Some(&start), Some(&end)) => {
                let entries = start as usize..end as usize;
                Square {
                    boxes: &self.boxes[entries.clone()],
                    ranges: &self.literal_ranges[entries],
                    literals: &self.literals,
                }
            }
            _ => Square {
                boxes: &[],
                ranges: &[],
                literals: &[],
            },
        }
    }
}

/// The columns of squares of a frame and, square by square, the boxes whose projection reaches
/// it (see [`FrameTiles::new`]).
fn square_lists(
    boxes: &[Aabb],
    camera: &Camera,
    size: ImageSize,
) -> Option<(u32, Vec<u32>, Vec<u32>)> {
    let columns = size.width().div_ceil(TILE);
    let rows = size.height().div_ceil(TILE);
    let mut squares = Vec::with_capacity(boxes.len());
    let mut total = 0u64;
    for (index, bounds) in boxes.iter().enumerate() {
        let Some(range) = square_range(bounds, camera, size, columns, rows) else {
            continue;
        };
        total += range.count();
        if total > MOST_LISTED {
            return None;
        }
        squares.push((index as u32, range));
    }
    let mut lists = vec![Vec::new(); (columns * rows) as usize];
    for (index, range) in squares {
        for row in range.rows.0..=range.rows.1 {
            for column in range.columns.0..=range.columns.1 {
                if range.outline.is_none_or(|o| o.reaches(column, row)) {
                    lists[(row * columns + column) as usize].push(index);
                }
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
    Some((columns, starts, flat))
}

/// The squares, inclusive ranges of columns and rows, whose pixels' rays may cross a box.
#[derive(Clone, Copy, Debug)]
struct SquareRange {
    columns: (u32, u32),
    rows: (u32, u32),
    /// The box's outline on the image, when it bounds the rays that may cross it.
    outline: Option<Outline>,
}

impl SquareRange {
    /// Whether rays of the square may cross the box.
    fn holds(&self, column: u32, row: u32) -> bool {
        (self.columns.0..=self.columns.1).contains(&column)
            && (self.rows.0..=self.rows.1).contains(&row)
            && self.outline.is_none_or(|o| o.reaches(column, row))
    }

    fn count(&self) -> u64 {
        u64::from(self.columns.1 - self.columns.0 + 1) * u64::from(self.rows.1 - self.rows.0 + 1)
    }
}

/// The squares whose rays may cross `bounds`; `None` for an empty box or one that projects
/// outside the frame.
fn square_range(
    bounds: &Aabb,
    camera: &Camera,
    size: ImageSize,
    columns: u32,
    rows: u32,
) -> Option<SquareRange> {
    if bounds.is_empty() {
        return None;
    }
    let ((x0, x1, y0, y1), outline) = match covered(bounds, camera, size) {
        Coverage::Nowhere => return None,
        Coverage::Everywhere => {
            return Some(SquareRange {
                columns: (0, columns - 1),
                rows: (0, rows - 1),
                outline: None,
            });
        }
        Coverage::Pixels(pixels, outline) => (pixels, outline),
    };
    Some(SquareRange {
        columns: (x0 / TILE, x1 / TILE),
        rows: (y0 / TILE, y1 / TILE),
        outline,
    })
}

/// Which pixels' rays may cross a box.
enum Coverage {
    /// None: the box projects outside the frame.
    Nowhere,
    /// Any: the projection cannot bound them (a corner not strictly in front of the eye, or
    /// not finite).
    Everywhere,
    /// Those of `(x0, x1, y0, y1)`, inclusive and within the frame, and among them those
    /// near the box's outline, when it has one.
    Pixels((u32, u32, u32, u32), Option<Outline>),
}

/// The pixels whose rays may cross `bounds`.
fn covered(bounds: &Aabb, camera: &Camera, size: ImageSize) -> Coverage {
    let (half_height, aspect) = camera.screen_scale();
    let (width, height) = (f64::from(size.width()), f64::from(size.height()));
    let (mut left, mut right) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut top, mut bottom) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut corners = [(0.0, 0.0); 8];
    for (corner, projected) in (0..8).zip(&mut corners) {
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
        *projected = (x, y);
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
    Coverage::Pixels(
        (
            first(left, width) as u32,
            last(right, width) as u32,
            first(top, height) as u32,
            last(bottom, height) as u32,
        ),
        Outline::around(&corners),
    )
}

/// The outline of a box on the image: the convex hull of its corners' projections (in pixel
/// coordinates), which holds the projection of the whole box (the projection of a convex body
/// is the hull of its vertices' projections). A square whose pixels, grown by [`MARGIN`],
/// all lie beyond one of its edges sees none of the box.
#[derive(Clone, Copy, Debug)]
struct Outline {
    /// The hull's corners, counter-clockwise in pixel coordinates.
    corners: [(f64, f64); 8],
    len: usize,
}

impl Outline {
    /// The hull of `points`; `None` when it is degenerate (a segment or a point), where the
    /// rectangle alone bounds the box.
    fn around(points: &[(f64, f64); 8]) -> Option<Self> {
        let mut sorted = *points;
        sorted.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        let cross = |o: (f64, f64), a: (f64, f64), b: (f64, f64)| {
            (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
        };
        // Andrew's monotone chain: the lower hull, then the upper one.
        let mut hull = [(0.0, 0.0); 17];
        let mut len = 0;
        for pass in 0..2 {
            let floor = len;
            let points: &mut dyn Iterator<Item = &(f64, f64)> = if pass == 0 {
                &mut sorted.iter()
            } else {
                &mut sorted.iter().rev()
            };
            for &p in points {
                while len >= floor + 2 && cross(hull[len - 2], hull[len - 1], p) <= 0.0 {
                    len -= 1;
                }
                hull[len] = p;
                len += 1;
            }
            // The last point of each chain begins the other.
            len -= 1;
        }
        if len < 3 {
            return None;
        }
        let mut corners = [(0.0, 0.0); 8];
        corners[..len.min(8)].copy_from_slice(&hull[..len.min(8)]);
        (len <= 8).then_some(Self { corners, len })
    }

    /// Whether some pixel of the square `(column, row)`, grown by [`MARGIN`], lies within the
    /// outline (or near it: the test is on the square's corners against each edge).
    fn reaches(&self, column: u32, row: u32) -> bool {
        let (x0, y0) = (f64::from(column * TILE), f64::from(row * TILE));
        // Pixel centres lie at half-integers: those of the square span [x0 + 0.5, x0 + TILE - 0.5].
        let (left, right) = (x0 + 0.5 - MARGIN, x0 + f64::from(TILE) - 0.5 + MARGIN);
        let (top, bottom) = (y0 + 0.5 - MARGIN, y0 + f64::from(TILE) - 0.5 + MARGIN);
        let square = [(left, top), (right, top), (right, bottom), (left, bottom)];
        (0..self.len).all(|k| {
            let a = self.corners[k];
            let b = self.corners[(k + 1) % self.len];
            // Counter-clockwise: the inside lies to the left of each edge.
            square
                .iter()
                .any(|&p| (b.0 - a.0) * (p.1 - a.1) - (b.1 - a.1) * (p.0 - a.0) >= 0.0)
        })
    }
}
