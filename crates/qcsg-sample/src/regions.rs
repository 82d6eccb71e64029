//! Low-distortion regions of the sampling-plane heightfields (paper §4.1), as basic regions.
//!
//! Every quadric has three sampling planes through its centre (paper §3.2; [`Heightfield`] in
//! `qcsg-quadric`). Over a plane the surface is one sheet (`Polynomial`: planes, paraboloids seen
//! along their axis), two sheets `t = ±√S` (`Root`), or nothing (`Ruled`: lines along the plane
//! normal lie in the surface, as for cylinders along their axis; the two planes that contain the
//! ruling direction cover that surface). The domain of each plane is the cross-section of the
//! term's box, split into quadrants at the plane's axes.
//!
//! **Decision (deviation from the analytic construction).** The paper bounds the region of
//! each quadrant where this plane is the best one ("up" is the largest normal component, so
//! `δ ≤ √3`) analytically by lines and the axis-aligned conics of eqs. 15-16, and cuts it into
//! triangles, rectangles, elliptic and hyperbolic triangles. Here the same region is found by a
//! refinement into axis-aligned rectangles (the paper's second basic kind), deciding the two
//! conditions of eqs. 15-16 exactly over a rectangle ([`BestPlane`]: each is a sum of a
//! quadratic in `x` and one in `y`) together with the rectangle distortion bound of §3.4:
//! - a rectangle where the plane is nowhere the best (one condition fails throughout), or whose
//!   minimum distortion exceeds `√3`, is dropped; so is one with no surface over it
//!   (`max S < 0`);
//! - a rectangle where the plane is the best everywhere becomes a basic region (its distortion
//!   is at most `√3`);
//! - a rectangle where it is the best in part becomes a *border* region once its distortion is
//!   at most [`KEEP_DISTORTION`]: its region is only the part where this plane is the best, and
//!   the subdivision drops the sub-rectangles and fill cells where it is nowhere the best
//!   ([`BasicRegion::owns_none_of`]), so the region ends at the conics of eqs. 15-16 up to the
//!   subdivision's resolution (one fill cell) instead of at a staircase of rectangles;
//! - anything else is split in two across the coordinate along which the distortion varies
//!   more (a cylinder seen from a plane holding its axis varies across it only).
//!
//! Only rectangles that provably hold no point where the plane is the best are dropped, so the
//! regions of the three planes cover every surface point (its best plane has a heightfield
//! there: the three normal components cannot all be below `1/√3`, and a ruled plane's normal
//! component is zero). Planes overlap only in the cells the border crosses. Earlier rules
//! sampled more of the surface from two planes: keeping every rectangle of distortion at most 2
//! sampled most of a sphere twice, and a staircase of whole border rectangles (1/16 of the
//! domain) took more samples than border regions (`docs/sampler-benchmarks.md`).
//! Rectangles still undecided after [`MAX_REGION_DEPTH`] splits (only around points where the
//! distortion is undefined, like a cone's apex seen from the side, at `2⁻⁴⁰` of the domain) are
//! counted in [`RegionStats::unresolved`] and dropped; around a cone's apex [`crate::apex`]
//! then settles them.
//!
//! **Following the radius, not the features.** Both kinds of refinement above end at the
//! scale of the surface's features: the band beside a border where the distortion is between
//! `√3` and [`KEEP_DISTORTION`], and the band beside a `Root` heightfield's rim where the plane
//! is still the best, are as narrow as the surface turns fast (`10⁻³` beside the waist of a
//! flat hyperboloid). A rectangle still to be split whose surface fits in a world box of
//! diagonal at most the radius is kept whole as a small patch instead, which one sample
//! settles ([`crate::small_patches`]); the partition's work then follows the surface's area
//! over the radius squared. A rectangle across a rim, whose distortion bounds cannot choose
//! the cut, is cut across the coordinate along which the radicand varies more
//! ([`radicand_cut`]), not at its longer edge, which cut a needle's rim into squares of its
//! width. The regions kept are charged to a [`RegionCap`], the run's sample limit: each is
//! held with eq. 22 narrowed to it until the run ends.

pub use crate::region_cap::{Held, REGION_SAMPLES, RegionCap};
use qcsg_csg::Aabb;
use qcsg_quadric::{DVec3, Heightfield, HeightfieldForm, PrincipalFrame};

/// A rectangle on the border between two planes' regions becomes a basic region only if its
/// maximum distortion is at most this.
pub const KEEP_DISTORTION: f64 = 2.0;

/// A rectangle that holds a cone's apex and whose surface lies within this fraction of the
/// radius of the apex is given up to the apex's ring of samples ([`crate::apex`]), which
/// covers what lies within a quarter of the ring's distance from the apex: rings at `r/2`,
/// `r/8` and `r/32` stay open to it.
pub const APEX_REACH: f64 = 1.0 / 256.0;

/// Splits after which an undecided rectangle is given up (see the module doc).
pub const MAX_REGION_DEPTH: u32 = 80;

/// Rectangles examined per sampling plane before the rest is given up (never reached on the
/// kinds the tests cover; a guard against pathological inputs).
pub const MAX_REGION_RECTANGLES: u64 = 1 << 22;

const SQRT3: f64 = 1.732_050_807_568_877_2;

/// An axis-aligned rectangle `[x.0, x.1] × [y.0, y.1]` of a sampling plane's domain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    /// The `x` interval (along the plane's first axis).
    pub x: (f64, f64),
    /// The `y` interval (along the plane's second axis).
    pub y: (f64, f64),
}

impl Rect {
    /// Width along `x`.
    pub fn width(&self) -> f64 {
        self.x.1 - self.x.0
    }

    /// Height along `y`.
    pub fn height(&self) -> f64 {
        self.y.1 - self.y.0
    }

    /// Length of the diagonal.
    pub fn diagonal(&self) -> f64 {
        // `hypot` is a call into libm on the hot path: only where the squares over- or
        // underflow.
        let (w, h) = (self.width(), self.height());
        let d = (w * w + h * h).sqrt();
        if d.is_normal() { d } else { w.hypot(h) }
    }

    /// The centre.
    pub fn centre(&self) -> (f64, f64) {
        (0.5 * (self.x.0 + self.x.1), 0.5 * (self.y.0 + self.y.1))
    }

    /// The four quadrants, split at the centre.
    pub fn quadrants(&self) -> [Rect; 4] {
        let (cx, cy) = self.centre();
        let (xs, ys) = (
            [(self.x.0, cx), (cx, self.x.1)],
            [(self.y.0, cy), (cy, self.y.1)],
        );
        std::array::from_fn(|k| Rect {
            x: xs[k / 2],
            y: ys[k % 2],
        })
    }

    /// Whether `(x, y)` lies in the closed rectangle.
    pub fn contains(&self, x: f64, y: f64) -> bool {
        self.x.0 <= x && x <= self.x.1 && self.y.0 <= y && y <= self.y.1
    }

    /// The two halves across the longer edge, and whether the split was along `x`.
    pub fn split_longest(&self) -> (Rect, Rect, bool) {
        let along_x = self.width() >= self.height();
        let (low, high) = self.split(along_x);
        (low, high, along_x)
    }

    /// The two halves across the middle of `x` (`along_x`) or of `y`.
    pub fn split(&self, along_x: bool) -> (Rect, Rect) {
        if along_x {
            let m = 0.5 * (self.x.0 + self.x.1);
            (
                Rect {
                    x: (self.x.0, m),
                    y: self.y,
                },
                Rect {
                    x: (m, self.x.1),
                    y: self.y,
                },
            )
        } else {
            let m = 0.5 * (self.y.0 + self.y.1);
            (
                Rect {
                    x: self.x,
                    y: (self.y.0, m),
                },
                Rect {
                    x: self.x,
                    y: (m, self.y.1),
                },
            )
        }
    }
}

/// One basic region: a rectangle of one sheet of one heightfield of one literal of one term.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BasicRegion {
    /// Index of the quadric in the DNF's quadric table.
    pub quadric: u32,
    /// Index of the term the quadric is sampled for.
    pub term: u32,
    /// The heightfield (its `normal_axis` names the sampling plane).
    pub heightfield: Heightfield,
    /// `+1` or `−1`: which sheet `t = ±h` of a `Root` heightfield; `+1` for `Polynomial`.
    pub sheet: f64,
    /// The rectangle in plane coordinates.
    pub rect: Rect,
    /// An upper bound of the distortion over the rectangle (§3.4).
    pub max_distortion: f64,
    /// Where the rectangle straddles the border of the plane's region, the test of where the
    /// plane is the best: the region is then only that part of the rectangle, and the
    /// subdivision leaves the rest, which other planes' regions hold, alone
    /// ([`BasicRegion::owns_none_of`]). `None` where the plane is the best throughout.
    pub border: Option<BestPlane>,
}

impl BasicRegion {
    /// Whether no point of `rect` (inside the region's rectangle) belongs to the region: a
    /// border region's rectangle where another plane is the best throughout. Another plane's
    /// region holds every such surface point, so the subdivision drops these rectangles; this
    /// makes the region the paper's analytic shape (bounded by the conics of eqs. 15-16) up to
    /// the subdivision's resolution.
    pub fn owns_none_of(&self, rect: &Rect) -> bool {
        self.owns(rect) == Owned::None
    }

    /// Whether every point of `rect` belongs to the region.
    pub fn owns_all_of(&self, rect: &Rect) -> bool {
        self.owns(rect) == Owned::All
    }

    /// How much of `rect` belongs to the region ([`Self::owns_none_of`], [`Self::owns_all_of`]).
    pub fn owns(&self, rect: &Rect) -> Owned {
        match self.border.as_ref().map(|best| best.over(rect)) {
            None | Some(Best::Everywhere) => Owned::All,
            Some(Best::Nowhere) => Owned::None,
            Some(Best::Partly) => Owned::Part,
        }
    }
}

/// How much of a rectangle belongs to a basic region ([`BasicRegion::owns`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Owned {
    /// Every point.
    All,
    /// Some points, or it could not be told.
    Part,
    /// No point: another plane is the best throughout.
    None,
}

/// Counters of the region decomposition.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RegionStats {
    /// Rectangles examined.
    pub examined: u64,
    /// Rectangles given up after [`MAX_REGION_DEPTH`] splits.
    pub unresolved: u64,
}

impl RegionStats {
    /// Adds another set of counters.
    pub fn add(&mut self, other: &Self) {
        self.examined += other.examined;
        self.unresolved += other.unresolved;
    }
}

enum RectClass {
    /// A basic region, with its maximum distortion and whether it straddles the border.
    Keep(f64, bool),
    Drop,
    /// Split across the coordinate along which the distortion varies more.
    Split,
}

/// The sampling planes' domains over a world box: the box's 8 corners in plane coordinates.
pub fn plane_domain(frame: &PrincipalFrame, heightfield: &Heightfield, bounds: &Aabb) -> Rect {
    let (i, j) = heightfield.plane_axes;
    let mut x = (f64::INFINITY, f64::NEG_INFINITY);
    let mut y = (f64::INFINITY, f64::NEG_INFINITY);
    for corner in bounds.corners() {
        let f = frame.to_frame(corner).to_array();
        x = (x.0.min(f[i]), x.1.max(f[i]));
        y = (y.0.min(f[j]), y.1.max(f[j]));
    }
    Rect { x, y }
}

/// The basic regions of `heightfield` over the world box `bounds`, appended to `out` in a
/// deterministic order (quadrants, then depth-first, lower half first). Returns how far from
/// the frame's centre the surface over the rectangles given up reaches (0 when none was;
/// [`crate::apex`] settles those around a cone's apex).
pub fn basic_regions(
    frame: &PrincipalFrame,
    heightfield: &Heightfield,
    bounds: &Aabb,
    key: (u32, u32),
    out: &mut Vec<BasicRegion>,
    stats: &mut RegionStats,
) -> f64 {
    let cap = RegionCap::new(u64::MAX);
    let none = SmallPatches::NONE;
    basic_regions_within(frame, heightfield, (bounds, none), key, (out, &cap), stats)
}

/// [`basic_regions`], charging every region kept to `cap`: once the cap is crossed the
/// decomposition stops, and what it found is incomplete ([`RegionCap::crossed`] says so).
pub fn basic_regions_within(
    frame: &PrincipalFrame,
    heightfield: &Heightfield,
    (bounds, small_patch): (&Aabb, SmallPatches),
    (quadric, term): (u32, u32),
    (out, cap): (&mut Vec<BasicRegion>, &RegionCap),
    stats: &mut RegionStats,
) -> f64 {
    let sheets: &[f64] = match heightfield.form {
        HeightfieldForm::Root { .. } => &[1.0, -1.0],
        HeightfieldForm::Polynomial { .. } => &[1.0],
        HeightfieldForm::Ruled => return 0.0,
    };
    let domain = plane_domain(frame, heightfield, bounds);
    let finite = [domain.x.0, domain.x.1, domain.y.0, domain.y.1]
        .iter()
        .all(|v| v.is_finite());
    if !finite || domain.width() <= 0.0 || domain.height() <= 0.0 {
        return 0.0;
    }
    let partition = Partition {
        frame,
        heightfield,
        small_patch,
        sheets: sheets.len() as u64,
        quadric,
        cap,
    };
    let (kept, given_up_reach) = partition.run(quadrants(domain), stats);
    for &sheet in sheets {
        out.extend(
            kept.iter()
                .map(|&(rect, max_distortion, border)| BasicRegion {
                    quadric,
                    term,
                    heightfield: *heightfield,
                    sheet,
                    rect,
                    max_distortion,
                    border: border.then(|| BestPlane::new(heightfield)),
                }),
        );
    }
    given_up_reach
}

/// Which rectangles the partition keeps whole as small patches (`small_patches.rs`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmallPatches {
    /// A rectangle to be split whose surface fits in a world box of this diagonal is kept
    /// whole; `0` keeps none.
    pub diagonal: f64,
    /// Whether the frame's centre is a cone's apex, which no small patch may hold: the normal
    /// turns all the way round within any distance of it, and the rectangles given up there
    /// are settled at the apex ([`crate::apex`]). Elsewhere a cone is as any quadric (a flat
    /// elliptic cone's thin edges took millions of regions when cones kept none).
    pub apex: bool,
}

impl SmallPatches {
    /// No small patch: every rectangle is refined until it is decided.
    pub const NONE: Self = Self {
        diagonal: 0.0,
        apex: false,
    };
}

/// The refinement of rectangles into basic regions, for one heightfield.
pub(crate) struct Partition<'a> {
    pub(crate) frame: &'a PrincipalFrame,
    pub(crate) heightfield: &'a Heightfield,
    /// Which rectangles to be split are kept as small patches instead.
    pub(crate) small_patch: SmallPatches,
    /// Regions each kept rectangle makes (one per sheet), charged to `cap`.
    pub(crate) sheets: u64,
    pub(crate) quadric: u32,
    pub(crate) cap: &'a RegionCap,
}

impl Partition<'_> {
    /// The rectangles kept from `roots` (each inside one quadrant of the plane), with their
    /// maximum distortion ([`f64::INFINITY`] for a small patch) and whether they straddle the
    /// border, depth first, lower half first; and how far from the frame's centre the surface
    /// over the rectangles given up reaches.
    pub(crate) fn run(
        &self,
        roots: Vec<Rect>,
        stats: &mut RegionStats,
    ) -> (Vec<(Rect, f64, bool)>, f64) {
        let heightfield = self.heightfield;
        let mut given_up_reach = 0.0f64;
        let mut kept = Vec::new();
        let mut budget = MAX_REGION_RECTANGLES;
        let best = BestPlane::new(heightfield);
        // Each rectangle lies in one quadrant, where its corners' squared slopes bound its
        // distortion ([`corner_bounds`]): a split takes four new ones.
        let slope = |x: f64, y: f64| heightfield.slope_squared(x, y).unwrap_or(f64::NAN);
        'roots: for root in roots {
            let (x, y) = (root.x, root.y);
            let slopes = [
                slope(x.0, y.0),
                slope(x.1, y.0),
                slope(x.0, y.1),
                slope(x.1, y.1),
            ];
            let mut stack = vec![((root, slopes), 0u32)];
            while let Some(((rect, slopes), depth)) = stack.pop() {
                stats.examined += 1;
                budget = budget.saturating_sub(1);
                let keep = match classify_rect(heightfield, &best, (&rect, corner_bounds(slopes))) {
                    RectClass::Keep(max_distortion, border) => Some((max_distortion, border)),
                    RectClass::Drop => None,
                    // Refining it for its distortion, or to tell where the rim of its
                    // heightfield crosses it, would only cut a patch that one sample can
                    // cover into many regions.
                    RectClass::Split if self.is_small_patch(&rect) => Some((f64::INFINITY, true)),
                    RectClass::Split
                        if depth >= MAX_REGION_DEPTH || budget == 0 || self.left_to_apex(&rect) =>
                    {
                        stats.unresolved += 1;
                        given_up_reach = given_up_reach.max(reach_from_centre(heightfield, &rect));
                        None
                    }
                    RectClass::Split => {
                        let cut = |rect: &Rect| radicand_cut(heightfield, rect);
                        let [low, high] = split_at_corners(heightfield, &rect, slopes, cut);
                        stack.push((high, depth + 1));
                        stack.push((low, depth + 1));
                        None
                    }
                };
                if let Some((max_distortion, border)) = keep {
                    if !self.cap.charge(self.sheets, self.quadric) {
                        break 'roots;
                    }
                    kept.push((rect, max_distortion, border));
                }
            }
        }
        (kept, given_up_reach)
    }

    /// Whether `rect` holds a cone's apex (the frame's centre, over the plane's origin).
    fn holds_apex(&self, rect: &Rect) -> bool {
        let holds_centre = |(low, high): (f64, f64)| low <= 0.0 && 0.0 <= high;
        self.small_patch.apex && holds_centre(rect.x) && holds_centre(rect.y)
    }

    /// Whether `rect`, which holds a cone's apex, is left to the apex's ring of samples
    /// ([`crate::apex`]) unrefined: where the surface over it lies within [`APEX_REACH`] of
    /// the small patches' diagonal of the apex. Refined further, it would leave beside the
    /// apex a small patch (a sample) for every halving down to [`MAX_REGION_DEPTH`].
    fn left_to_apex(&self, rect: &Rect) -> bool {
        self.holds_apex(rect)
            && reach_from_centre(self.heightfield, rect) <= APEX_REACH * self.small_patch.diagonal
    }

    /// Whether the surface over `rect` (both sheets) fits in a world box of the small patches'
    /// diagonal, and holds no cone's apex.
    fn is_small_patch(&self, rect: &Rect) -> bool {
        let diagonal = self.small_patch.diagonal;
        if diagonal <= 0.0 || self.holds_apex(rect) {
            return false;
        }
        let region = |sheet: f64| BasicRegion {
            quadric: self.quadric,
            term: 0,
            heightfield: *self.heightfield,
            sheet,
            rect: *rect,
            max_distortion: f64::INFINITY,
            border: None,
        };
        [1.0, -1.0].iter().all(|&sheet| {
            patch_bounds(self.frame, &region(sheet))
                .is_some_and(|b| (b.max - b.min).length() <= diagonal)
        })
    }
}

/// How far from the frame's centre the surface over `rect` reaches: `√(x² + y² + S)` at most,
/// in the frame's coordinates (`+∞` but for a `Root` heightfield).
fn reach_from_centre(heightfield: &Heightfield, rect: &Rect) -> f64 {
    let Some(s_max) = radicand_max(heightfield, rect) else {
        return f64::INFINITY;
    };
    let far = |(a, b): (f64, f64)| a.abs().max(b.abs());
    let squared = far(rect.x).powi(2) + far(rect.y).powi(2) + s_max.max(0.0);
    // A hair more, for rounding in the bound.
    squared.sqrt() * (1.0 + 1e-9)
}

/// The halves of an undecided rectangle: split where the distortion varies. The distortion of
/// a cylinder seen from a plane holding its axis depends on one coordinate only; halving the
/// other (the longer edge of a tall domain) would not bring the rectangle closer to a decision.
/// Of the two cuts, the one whose halves have the smaller largest spread of distortion wins;
/// the longer edge breaks ties and decides where the bounds are undefined. Each half comes with
/// its bounds ([`Heightfield::distortion_bounds`]), which the callers need next.
pub fn split_for_distortion(heightfield: &Heightfield, rect: &Rect) -> [Bounded; 2] {
    let cut = |along_x: bool| {
        let (low, high) = rect.split(along_x);
        [low, high].map(|half| (half, heightfield.distortion_bounds(half.x, half.y)))
    };
    let (by_x, by_y) = (cut(true), cut(false));
    if cut_along_x(
        rect,
        [&by_x, &by_y].map(|halves| halves.map(|(_, bounds)| bounds)),
    ) {
        by_x
    } else {
        by_y
    }
}

/// [`split_for_distortion`] of a rectangle inside one quadrant of its plane, from the squared
/// slopes at its corners (`slopes`, [`Heightfield::slope_squared`] in the order `x0y0, x1y0,
/// x0y1, x1y1`, NaN where undefined): there a rectangle's bounds are those of its corners
/// ([`corner_bounds`]), so both cuts take four new slopes instead of sixteen. Each half comes
/// with its corners' slopes.
pub fn split_for_distortion_at_corners(
    heightfield: &Heightfield,
    rect: &Rect,
    slopes: [f64; 4],
) -> [(Rect, [f64; 4]); 2] {
    split_at_corners(heightfield, rect, slopes, |rect| {
        rect.width() >= rect.height()
    })
}

/// [`split_for_distortion_at_corners`], cutting across `x` where `undecided(rect)` says so
/// when the halves' distortion bounds do not decide.
fn split_at_corners(
    heightfield: &Heightfield,
    rect: &Rect,
    slopes: [f64; 4],
    undecided: impl Fn(&Rect) -> bool,
) -> [(Rect, [f64; 4]); 2] {
    let slope = |x: f64, y: f64| heightfield.slope_squared(x, y).unwrap_or(f64::NAN);
    let (mx, my) = rect.centre();
    let [a, b, c, d] = slopes;
    let ((x_low, x_high), (y_low, y_high)) = (rect.split(true), rect.split(false));
    let (bottom, top) = (slope(mx, rect.y.0), slope(mx, rect.y.1));
    let (left, right) = (slope(rect.x.0, my), slope(rect.x.1, my));
    let by_x = [(x_low, [a, bottom, c, top]), (x_high, [bottom, b, top, d])];
    let by_y = [(y_low, [a, b, left, right]), (y_high, [left, right, c, d])];
    let bounds = |halves: &[(Rect, [f64; 4]); 2]| halves.map(|(_, s)| corner_bounds(s));
    let along_x = match cut_scores([bounds(&by_x), bounds(&by_y)]) {
        (x, y) if x.is_finite() && y.is_finite() && x != y => x < y,
        _ => undecided(rect),
    };
    if along_x { by_x } else { by_y }
}

/// The cut of a rectangle of [`basic_regions`] whose halves' distortion bounds do not decide
/// it (a `Root` heightfield's rim crosses it, where the slope is unbounded): across the
/// coordinate along which the radicand `S` varies more, so that the halves' ranges of `S`
/// shrink, which is what decides such a rectangle ([`partially_defined`]: it is dropped once
/// `S` is small beside the gradient). The longer edge would cut a long thin sheet (a
/// paraboloid `10⁸` long and `74` wide seen from the side, an ellipsoid `10⁶` long) into
/// squares of its width all along its rim: millions of rectangles, and as many basic regions,
/// however coarse the radius.
fn radicand_cut(heightfield: &Heightfield, rect: &Rect) -> bool {
    let HeightfieldForm::Root {
        alpha_x,
        alpha_y,
        beta_x,
        beta_y,
        ..
    } = heightfield.form
    else {
        return rect.width() >= rect.height();
    };
    // The range of `S`'s part in one coordinate over the whole interval, and the larger of
    // its ranges over the two halves.
    let spread = |alpha: f64, beta: f64, (a, b): (f64, f64)| {
        let parabola = Parabola::new(alpha, beta);
        let mid = 0.5 * (a + b);
        let halves = [(a, mid), (mid, b)].map(|half| {
            let (low, high) = parabola.range(half);
            high - low
        });
        let (low, high) = parabola.range((a, b));
        (high - low, halves[0].max(halves[1]))
    };
    let (whole_x, halved_x) = spread(alpha_x, beta_x, rect.x);
    let (whole_y, halved_y) = spread(alpha_y, beta_y, rect.y);
    // The largest range of `S` over a half, for each cut.
    let (by_x, by_y) = (halved_x + whole_y, whole_x + halved_y);
    if by_x.is_finite() && by_y.is_finite() && by_x != by_y {
        by_x < by_y
    } else {
        rect.width() >= rect.height()
    }
}

/// [`Heightfield::distortion_bounds`] of a rectangle inside one quadrant from its corners'
/// squared slopes (NaN where undefined), rounded as it rounds them.
pub fn corner_bounds(slopes: [f64; 4]) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for slope in slopes {
        if slope.is_nan() {
            return None;
        }
        lo = lo.min(slope);
        hi = hi.max(slope);
    }
    Some(((1.0 + lo).sqrt(), (1.0 + hi).sqrt()))
}

/// Whether [`split_for_distortion`] cuts across `x`, from the bounds of the halves of the cut
/// across `x` and of the cut across `y`.
fn cut_along_x(rect: &Rect, cuts: [[Option<(f64, f64)>; 2]; 2]) -> bool {
    let (score_x, score_y) = cut_scores(cuts);
    if score_x.is_finite() && score_y.is_finite() && score_x != score_y {
        score_x < score_y
    } else {
        rect.width() >= rect.height()
    }
}

/// The largest spread of the distortion bounds over the halves of the cut across `x` and of
/// the cut across `y` (infinite where a half has none).
fn cut_scores([by_x, by_y]: [[Option<(f64, f64)>; 2]; 2]) -> (f64, f64) {
    let score = |halves: [Option<(f64, f64)>; 2]| {
        let spread =
            |bounds: Option<(f64, f64)>| bounds.map_or(f64::INFINITY, |(low, high)| high - low);
        spread(halves[0]).max(spread(halves[1]))
    };
    (score(by_x), score(by_y))
}

/// A rectangle with its distortion bounds ([`Heightfield::distortion_bounds`]).
pub type Bounded = (Rect, Option<(f64, f64)>);

/// The domain cut at the plane's axes (the paper describes one quadrant; the rest is symmetry).
fn quadrants(domain: Rect) -> Vec<Rect> {
    let cut = |(a, b): (f64, f64)| {
        if a < 0.0 && b > 0.0 {
            vec![(a, 0.0), (0.0, b)]
        } else {
            vec![(a, b)]
        }
    };
    let mut out = Vec::new();
    for y in cut(domain.y) {
        for x in cut(domain.x) {
            out.push(Rect { x, y });
        }
    }
    out
}

/// What to do with a rectangle of distortion bounds `bounds`.
fn classify_rect(
    heightfield: &Heightfield,
    best: &BestPlane,
    (rect, bounds): (&Rect, Option<(f64, f64)>),
) -> RectClass {
    if rect.width() <= 0.0 || rect.height() <= 0.0 {
        return RectClass::Drop;
    }
    match bounds {
        Some((low, _)) if low > SQRT3 => RectClass::Drop,
        Some((_, high)) => match best.over(rect) {
            Best::Nowhere => RectClass::Drop,
            Best::Everywhere => RectClass::Keep(high, false),
            Best::Partly if high <= KEEP_DISTORTION => RectClass::Keep(high, true),
            Best::Partly => RectClass::Split,
        },
        None => partially_defined(heightfield, rect),
    }
}

/// Where over a rectangle this sampling plane is the best one (paper §4.1: the normal
/// component along the plane's normal is the largest).
enum Best {
    Everywhere,
    Nowhere,
    Partly,
}

/// Where over a rectangle a sampling plane is the best one, decided exactly up to rounding:
/// with `n ∝ (g_x, g_y, t)` the conditions `t² ≥ g_x²` and `t² ≥ g_y²` are differences of
/// quadratics that separate into a part in `x` and a part in `y` (eqs. 15-16), so their ranges
/// over a rectangle are sums of two quadratic ranges. Built once per region, with the vertices
/// of its parabolas: the subdivision asks it for every cell and fill row of a border region,
/// and the divisions that find the vertices had taken most of its time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BestPlane {
    /// Each condition `a_x x² + 2 b_x x + a_y y² + 2 b_y y + c ≥ 0` as its parabolas in `x` and
    /// `y` and `c`; `None` for a ruled heightfield, whose plane is the best nowhere.
    conditions: Option<[(Parabola, Parabola, f64); 2]>,
}

impl BestPlane {
    /// The test for the plane of `heightfield`.
    pub fn new(heightfield: &Heightfield) -> Self {
        let conditions = match heightfield.form {
            HeightfieldForm::Root {
                alpha_x: ax,
                alpha_y: ay,
                alpha_c: c,
                beta_x: bx,
                beta_y: by,
            } => Some([
                // S − g_x², g_x = α_x x + β_x.
                (
                    Parabola::new(ax - ax * ax, bx * (1.0 - ax)),
                    Parabola::new(ay, by),
                    c - bx * bx,
                ),
                // S − g_y².
                (
                    Parabola::new(ax, bx),
                    Parabola::new(ay - ay * ay, by * (1.0 - ay)),
                    c - by * by,
                ),
            ]),
            HeightfieldForm::Polynomial {
                gamma_x, gamma_y, ..
            } => Some([
                // 1 − (2 γ_x x)² and 1 − (2 γ_y y)².
                (
                    Parabola::new(-4.0 * gamma_x * gamma_x, 0.0),
                    Parabola::new(0.0, 0.0),
                    1.0,
                ),
                (
                    Parabola::new(0.0, 0.0),
                    Parabola::new(-4.0 * gamma_y * gamma_y, 0.0),
                    1.0,
                ),
            ]),
            HeightfieldForm::Ruled => None,
        };
        Self { conditions }
    }

    /// Where over `rect` the plane is the best. `Nowhere` needs one condition to fail by more
    /// than rounding everywhere.
    fn over(&self, rect: &Rect) -> Best {
        let Some(conditions) = &self.conditions else {
            return Best::Nowhere;
        };
        let mut everywhere = true;
        for (in_x, in_y, c) in conditions {
            let ((low_x, high_x), (low_y, high_y)) = (in_x.range(rect.x), in_y.range(rect.y));
            let (low, high) = (low_x + low_y + c, high_x + high_y + c);
            // NaN never drops a rectangle; the rounding scale matters only below zero.
            if high < 0.0 && high < -1e-12 * low.abs().max(high.abs()).max(c.abs()) {
                return Best::Nowhere;
            }
            everywhere &= low >= 0.0;
        }
        if everywhere {
            Best::Everywhere
        } else {
            Best::Partly
        }
    }
}

/// `α v² + 2β v`, with its vertex `−β / α`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Parabola {
    alpha: f64,
    beta: f64,
    vertex: f64,
}

impl Parabola {
    /// `α v² + 2β v`, its vertex found once.
    fn new(alpha: f64, beta: f64) -> Self {
        Self {
            alpha,
            beta,
            vertex: -beta / alpha,
        }
    }

    /// Its least and greatest values over `[a, b]`: at the ends, or at the vertex inside.
    fn range(&self, (a, b): (f64, f64)) -> (f64, f64) {
        let f = |v: f64| (self.alpha * v + 2.0 * self.beta) * v;
        let (at_a, at_b) = (f(a), f(b));
        let (mut low, mut high) = (at_a.min(at_b), at_a.max(at_b));
        if a < self.vertex && self.vertex < b {
            if self.alpha < 0.0 {
                high = high.max(f(self.vertex));
            } else if self.alpha > 0.0 {
                low = low.min(f(self.vertex));
            }
        }
        (low, high)
    }
}

/// The largest radicand `S` of a `Root` heightfield over `rect`; `None` for other forms.
fn radicand_max(heightfield: &Heightfield, rect: &Rect) -> Option<f64> {
    let HeightfieldForm::Root {
        alpha_x,
        alpha_y,
        alpha_c,
        beta_x,
        beta_y,
    } = heightfield.form
    else {
        return None;
    };
    let (_, in_x) = Parabola::new(alpha_x, beta_x).range(rect.x);
    let (_, in_y) = Parabola::new(alpha_y, beta_y).range(rect.y);
    Some(in_x + in_y + alpha_c)
}

/// Where over `rect` the radicand `S` of a `Root` heightfield is largest (the surface over it
/// is there if anywhere); the centre for other forms.
pub(crate) fn radicand_peak(heightfield: &Heightfield, rect: &Rect) -> (f64, f64) {
    let HeightfieldForm::Root {
        alpha_x,
        alpha_y,
        beta_x,
        beta_y,
        ..
    } = heightfield.form
    else {
        return rect.centre();
    };
    let peak = |parabola: Parabola, (a, b): (f64, f64)| {
        let f = |v: f64| (parabola.alpha * v + 2.0 * parabola.beta) * v;
        if parabola.alpha < 0.0 && a < parabola.vertex && parabola.vertex < b {
            parabola.vertex
        } else if f(b) > f(a) {
            b
        } else {
            a
        }
    };
    (
        peak(Parabola::new(alpha_x, beta_x), rect.x),
        peak(Parabola::new(alpha_y, beta_y), rect.y),
    )
}

/// A `Root` rectangle over which the radicand is negative somewhere: drop it if there is no
/// surface over it or if a lower bound of `δ² = 1 + |g|² / S` on its defined part exceeds 3.
fn partially_defined(heightfield: &Heightfield, rect: &Rect) -> RectClass {
    let (
        Some(s_max),
        HeightfieldForm::Root {
            alpha_x,
            alpha_y,
            beta_x,
            beta_y,
            ..
        },
    ) = (radicand_max(heightfield, rect), heightfield.form)
    else {
        return RectClass::Drop;
    };
    if !s_max.is_finite() {
        return RectClass::Split;
    }
    if s_max < 0.0 {
        return RectClass::Drop;
    }
    let gx = linear_min_abs(alpha_x, beta_x, rect.x);
    let gy = linear_min_abs(alpha_y, beta_y, rect.y);
    let slope = gx * gx + gy * gy;
    // With `S_max = 0` only rim points are defined, where the distortion is infinite.
    if slope > 2.0 * s_max {
        RectClass::Drop
    } else {
        RectClass::Split
    }
}

/// A world box holding the surface over a basic region's rectangle (its patch), slightly
/// widened for rounding; `None` where the heightfield has no form to bound.
pub fn patch_bounds(frame: &PrincipalFrame, region: &BasicRegion) -> Option<Aabb> {
    let rect = region.rect;
    let heights = match region.heightfield.form {
        HeightfieldForm::Root {
            alpha_x,
            alpha_y,
            alpha_c,
            beta_x,
            beta_y,
        } => {
            let (low_x, high_x) = Parabola::new(alpha_x, beta_x).range(rect.x);
            let (low_y, high_y) = Parabola::new(alpha_y, beta_y).range(rect.y);
            let (low, high) = (
                (low_x + low_y + alpha_c).max(0.0).sqrt(),
                (high_x + high_y + alpha_c).max(0.0).sqrt(),
            );
            if region.sheet > 0.0 {
                (low, high)
            } else {
                (-high, -low)
            }
        }
        HeightfieldForm::Polynomial {
            gamma_x,
            gamma_y,
            gamma_c,
        } => {
            let (low_x, high_x) = Parabola::new(gamma_x, 0.0).range(rect.x);
            let (low_y, high_y) = Parabola::new(gamma_y, 0.0).range(rect.y);
            (low_x + low_y + gamma_c, high_x + high_y + gamma_c)
        }
        HeightfieldForm::Ruled => return None,
    };
    // The prism over the rectangle, turned into the world: its centre, and its half-extents
    // along the frame's axes summed by their absolute values (the box around the prism's eight
    // corners, without transforming them: they took most of this function's time).
    let mid = |(low, high): (f64, f64)| (0.5 * (low + high), 0.5 * (high - low));
    let ((x, half_x), (y, half_y), (t, half_t)) = (mid(rect.x), mid(rect.y), mid(heights));
    let centre = frame.heightfield_point(&region.heightfield, x, y, t);
    let (i, j) = region.heightfield.plane_axes;
    let axes = [i, j, region.heightfield.normal_axis].map(|k| frame.axes[k].abs());
    let half = half_x * axes[0] + half_y * axes[1] + half_t * axes[2];
    let bounds = Aabb::new(centre - half, centre + half);
    let pad = 1e-9 * (bounds.max - bounds.min).length()
        + 1e-12 * bounds.max.abs().max(bounds.min.abs()).max_element();
    Some(bounds.expanded(pad))
}

/// `min |α v + β|` over `[a, b]`.
fn linear_min_abs(alpha: f64, beta: f64, (a, b): (f64, f64)) -> f64 {
    let (fa, fb) = (alpha * a + beta, alpha * b + beta);
    if fa.signum() != fb.signum() || fa == 0.0 || fb == 0.0 {
        0.0
    } else {
        fa.abs().min(fb.abs())
    }
}

/// The world point of plane coordinates `(x, y)` on `sheet`; `None` where there is no surface.
pub fn region_point(
    frame: &PrincipalFrame,
    heightfield: &Heightfield,
    sheet: f64,
    x: f64,
    y: f64,
) -> Option<DVec3> {
    let h = heightfield.height(x, y)?;
    Some(frame.heightfield_point(heightfield, x, y, sheet * h))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// A parabola's range over an interval holds its value at every point of a fine grid
        /// (up to rounding), and both ends of it are values at an end or at the vertex inside.
        #[test]
        fn parabola_range_is_the_least_and_greatest_value(
            alpha in prop_oneof![-4.0f64..4.0, Just(0.0), Just(-0.0)],
            beta in prop_oneof![-4.0f64..4.0, Just(0.0)],
            (a, width) in (-3.0f64..3.0, 0.0f64..4.0),
        ) {
            let (b, vertex) = (a + width, -beta / alpha);
            let f = |v: f64| (alpha * v + 2.0 * beta) * v;
            let (low, high) = Parabola::new(alpha, beta).range((a, b));
            let mut extremes = vec![f(a), f(b)];
            if a < vertex && vertex < b {
                extremes.push(f(vertex));
            }
            prop_assert!(extremes.contains(&low) && extremes.contains(&high));
            let reach = a.abs().max(b.abs());
            let slack = 1e-12 * (1.0 + alpha.abs() * reach * reach + 2.0 * beta.abs() * reach);
            for k in 0..=64 {
                let value = f(a + width * f64::from(k) / 64.0);
                prop_assert!(low - slack <= value && value <= high + slack, "{value} outside {low}..{high}");
            }
        }
    }
}
