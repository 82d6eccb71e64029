//! One notion of "the same surface": which quadrics of a DNF share a surface, up to a non-zero
//! factor and within the rounding of the transforms that placed them.
//!
//! A flush cutter's face and the part's face, a ball and a turned copy of it, the lateral
//! surfaces of two coaxial cylinders of one radius: each pair is one surface written twice, with
//! coefficients that differ in their last bits. Every consumer that compared them with a
//! tolerance of its own would draw (or sample) a speckled face where the two disagree; instead
//! the compiler decides here, once, and the ray tracer, pruning and the sampler use the answer.
//!
//! **Sheets.** A quadric's surface is cut into sheets: a half-space has one plane, a slab (or its
//! complement) two parallel planes, every other quadric with a surface one curved sheet, and a
//! quadric with no surface (all of space, nothing) none. A plane sheet can be the same surface
//! as a plane of another quadric (a slab's face and a half-space); a curved sheet only as a
//! whole quadric. Each sheet gets a [`Surface`] id and an orientation: `+1` when the quadric's
//! outward normal there agrees with the surface's (its first sheet's), `-1` when it is opposite
//! (a complement: the cutter of a flush difference).
//!
//! **Tolerance.** Every DNF quadric carries its [`Rounding`], derived from the transform that
//! placed it: a relative error `δ = 64 u κ²` of each group of its coefficients (`u = 2⁻⁵³`, `κ` the
//! ∞-norm condition number of the transform's linear part: 1 for translations, at most 3 for
//! rotations) and an absolute error `e = 8 u (‖L‖∞ |o|∞ + |t|∞)` of its origin (`o` the leaf's
//! origin, `L`, `t` the transform), which is what grows far from the world origin. Two planes are
//! one surface when their unit normals agree up to sign within `τ_n = 2(δ₁ + δ₂) + 8u` and each
//! one's reference point lies within `e₁ + e₂ + 8u (|p₁|∞ + |p₂|∞) + 2(δ₁ w₁ + δ₂ w₂) + 3 τ_n
//! |p₁ − p₂|∞` of the other's plane (`w` the plane's distance from its quadric's origin). Two
//! curved sheets are one surface when their coefficient vectors, expressed about the first one's
//! origin and balanced by its length unit (so that quadratic, linear and constant parts weigh
//! alike), agree up to a non-zero factor entrywise within `2(δ₁ + δ₂) + 6 (e₁ + e₂)/unit`, plus the
//! rounding bound of re-expanding the second about the first's origin. A thin wall, a ball
//! resting on a plane or two touching balls stay apart; a cube's face moved far away, turned or
//! scaled matches the face of a cutter placed the same way (`docs/compiler.md` has the numbers).
//!
//! **Finding them** costs near-linear time: each sheet is filed in a hash grid under invariants
//! that do not depend on its origin, scale or sign (a plane's `|n|` components and its distance
//! from the world origin; a curved sheet's centre set's point nearest the world origin), with
//! cells at least eight times the largest tolerance, so a match lies in the cell of the sheet or,
//! where the sheet's key lies within twice that tolerance of a cell's border, in the neighbour
//! across it (usually one cell is looked at). Only the first sheet of each surface is filed, and
//! at most [`MAX_CANDIDATES_PER_CELL`] of them are compared per cell (a scene of thousands of
//! distinct surfaces within rounding of each other is not a model).

use std::collections::{HashMap, HashSet};

use qcsg_quadric::{
    DMat4, DVec3, PrincipalFrame, Quadric, QuadricKind, Tolerances, classify_frame,
};

/// Unit roundoff of f64.
const U: f64 = f64::EPSILON / 2.0;

/// The relative error of a quadric's coefficient groups per unit of `κ²` (see the module docs).
pub const COEFFICIENT_ROUNDING: f64 = 64.0 * U;

/// The absolute error of a placed point per unit of the magnitudes it is computed from.
pub const POSITION_ROUNDING: f64 = 8.0 * U;

/// Surfaces compared per grid cell at most, to keep pathological scenes near-linear.
pub const MAX_CANDIDATES_PER_CELL: usize = 64;

/// The smallest grid cell relative to the scene's largest coordinate (`2⁻³⁰`): far above any
/// tolerance, so that a value's rounding rarely moves it to a neighbour's cell.
const CELL_FLOOR: f64 = 1.0 / (1u64 << 30) as f64;

/// The rounding a DNF quadric carries from the transform that placed it in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rounding {
    /// The relative error of each group of its coefficients (quadratic, linear, constant).
    pub relative: f64,
    /// The absolute error of its origin, a length.
    pub length: f64,
}

impl Default for Rounding {
    /// A quadric given in world space, its coefficients rounded once and its origin exact.
    fn default() -> Self {
        Self {
            relative: COEFFICIENT_ROUNDING,
            length: 0.0,
        }
    }
}

impl Rounding {
    /// The rounding of a leaf quadric with origin `local_origin` placed in world space by `m`.
    pub fn of_placement(m: &DMat4, local_origin: DVec3) -> Self {
        if *m == DMat4::IDENTITY {
            return Self::default();
        }
        let rows = |m: &DMat4, size: usize| {
            (0..size)
                .map(|r| (0..size).map(|c| m.col(c)[r].abs()).sum::<f64>())
                .fold(0.0f64, f64::max)
        };
        let affine = m.row(3).to_array() == [0.0, 0.0, 0.0, 1.0];
        let size = if affine { 3 } else { 4 };
        let norm = rows(m, size);
        let inverse = m.inverse();
        let condition = norm * rows(&inverse, size);
        let condition = if condition.is_finite() && condition >= 1.0 {
            condition
        } else {
            1.0
        };
        let placed =
            norm * local_origin.abs().max_element() + m.w_axis.truncate().abs().max_element();
        Self {
            relative: COEFFICIENT_ROUNDING * condition * condition,
            length: if placed.is_finite() {
                POSITION_ROUNDING * placed
            } else {
                0.0
            },
        }
    }
}

/// One sheet of a quadric's surface, as [`Surfaces::of`] lists them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sheet {
    /// The surface it is: sheets with equal ids are one surface.
    pub surface: u32,
    /// `+1` when the quadric's outward normal on this sheet is the surface's, `-1` opposite.
    pub orientation: i8,
    /// Whether the quadric's solid lies all on the inner side of this sheet: true for every
    /// sheet but those of a slab's complement (which holds both sides of the slab).
    pub one_sided: bool,
}

/// A surface shared by one or more sheets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    /// A quadric whose surface it is, oriented as the surface: for a plane, the half-space of
    /// its first sheet; for a curved surface, the first sheet's quadric. Every sheet of the
    /// surface meets a line where this quadric does.
    pub quadric: Quadric,
    /// Whether it is a plane.
    pub planar: bool,
    /// How many sheets lie on it.
    pub sheets: u32,
}

/// The surfaces of a DNF's quadrics: the sheets of each quadric and what they are.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Surfaces {
    /// `starts[i]..starts[i + 1]` are quadric `i`'s sheets.
    starts: Vec<u32>,
    sheets: Vec<Sheet>,
    surfaces: Vec<Surface>,
    /// Pairs of sheets compared while finding them.
    comparisons: usize,
}

impl Surfaces {
    /// The sheets of quadric `quadric` (none for a quadric without a surface); `None` for an
    /// index past the table the surfaces were found for.
    pub fn of(&self, quadric: u32) -> Option<&[Sheet]> {
        let i = quadric as usize;
        let (&start, &end) = (self.starts.get(i)?, self.starts.get(i + 1)?);
        self.sheets.get(start as usize..end as usize)
    }

    /// The surface with id `id`.
    pub fn surface(&self, id: u32) -> Option<&Surface> {
        self.surfaces.get(id as usize)
    }

    /// Number of distinct surfaces.
    pub fn len(&self) -> usize {
        self.surfaces.len()
    }

    /// Whether there are no surfaces.
    pub fn is_empty(&self) -> bool {
        self.surfaces.is_empty()
    }

    /// Number of quadrics described.
    pub fn quadric_count(&self) -> usize {
        self.starts.len().saturating_sub(1)
    }

    /// How many pairs of sheets were compared to find the surfaces: the work done, which stays
    /// near-linear in the number of sheets (see the module docs).
    pub fn comparisons(&self) -> usize {
        self.comparisons
    }

    /// Whether the solids of quadrics `a` and `b` meet only on a surface they share, so that a
    /// term holding both has no volume: a shared sheet with opposite orientations on which each
    /// lies on one side (`x ≤ 0` and `−x ≤ 0`; a ball and the complement of a turned copy of
    /// it), or every sheet shared with opposite orientations (a slab and its complement).
    pub fn meet_only_on_surface(&self, a: u32, b: u32) -> bool {
        let (Some(a), Some(b)) = (self.of(a), self.of(b)) else {
            return false;
        };
        let opposite =
            |x: &Sheet, y: &Sheet| x.surface == y.surface && x.orientation != y.orientation;
        let one_sided_pair = a
            .iter()
            .any(|x| x.one_sided && b.iter().any(|y| y.one_sided && opposite(x, y)));
        let all_opposite = !a.is_empty()
            && a.len() == b.len()
            && a.iter().all(|x| b.iter().any(|y| opposite(x, y)));
        one_sided_pair || all_opposite
    }
}

/// Whether the term of `literals` (indices into the quadrics of `surfaces`) holds two literals
/// that meet only on a surface they share ([`Surfaces::meet_only_on_surface`]): it has no
/// volume. Linear in the term's length: one-sided sheets are grouped by surface, and a literal
/// that is not one-sided (a slab's complement) is looked up by its sheets, flipped.
pub fn has_coincident_pair(surfaces: &Surfaces, literals: &[u32]) -> bool {
    let shared = |sheet: &Sheet| {
        surfaces
            .surface(sheet.surface)
            .is_some_and(|s| s.sheets > 1)
    };
    // Surfaces met by a one-sided sheet, with the orientations seen on each.
    let mut one_sided: HashMap<u32, i8> = HashMap::new();
    // Each literal's sheets as (surface, orientation) pairs, sorted.
    let mut whole: HashSet<Vec<(u32, i8)>> = HashSet::new();
    let mut two_sided: Vec<Vec<(u32, i8)>> = Vec::new();
    for &id in literals {
        let sheets = surfaces.of(id).unwrap_or_default();
        if sheets.is_empty() || !sheets.iter().any(shared) {
            continue;
        }
        for sheet in sheets.iter().filter(|s| s.one_sided && shared(s)) {
            let seen = one_sided.entry(sheet.surface).or_insert(sheet.orientation);
            if *seen != sheet.orientation {
                return true;
            }
        }
        let mut key: Vec<(u32, i8)> = sheets.iter().map(|s| (s.surface, s.orientation)).collect();
        key.sort_unstable();
        if sheets.iter().any(|s| !s.one_sided) {
            two_sided.push(key.clone());
        }
        whole.insert(key);
    }
    two_sided.into_iter().any(|key| {
        let flipped: Vec<(u32, i8)> = key.into_iter().map(|(s, o)| (s, -o)).collect();
        whole.contains(&flipped)
    })
}

/// Finds the surfaces of `quadrics` (each with its rounding), in order: surface ids are
/// numbered by first appearance, and each surface's orientation is its first sheet's.
pub fn find_surfaces<'a>(quadrics: impl IntoIterator<Item = (&'a Quadric, Rounding)>) -> Surfaces {
    let mut candidates: Vec<Candidate<'a>> = Vec::new();
    let mut starts = vec![0u32];
    for (q, rounding) in quadrics {
        sheets_of(q, rounding, &mut candidates);
        starts.push(candidates.len() as u32);
    }
    let mut finder = Finder {
        grid: Grid::for_candidates(&candidates),
        candidates: &candidates,
        planes: HashMap::new(),
        curved: HashMap::new(),
        filed: Filed {
            representatives: Vec::new(),
            surfaces: Surfaces {
                starts,
                sheets: Vec::with_capacity(candidates.len()),
                ..Surfaces::default()
            },
        },
    };
    for index in 0..candidates.len() {
        let sheet = finder.file(index);
        finder.filed.surfaces.sheets.push(sheet);
    }
    finder.filed.surfaces
}

/// What a sheet is, with its tolerances.
#[derive(Clone, Debug)]
struct Candidate<'a> {
    /// The quadric it is a sheet of.
    quadric: &'a Quadric,
    shape: Shape,
    one_sided: bool,
    rounding: Rounding,
}

#[derive(Clone, Debug)]
enum Shape {
    /// The plane through `point` (finite) with unit outward `normal`; `offset` is its distance
    /// from its quadric's origin.
    Plane {
        normal: DVec3,
        point: DVec3,
        offset: f64,
    },
    /// The whole quadric; `centre` is the point of its centre set nearest the world origin (an
    /// invariant of the surface), `unit` its length unit.
    Curved { centre: DVec3, unit: f64 },
}

impl Candidate<'_> {
    /// The tolerance of normals (planes).
    fn normal_tolerance(&self) -> f64 {
        2.0 * self.rounding.relative + 4.0 * U
    }

    /// A bound on how far this sheet's hash key may lie from a matching sheet's, when both lie
    /// within `extent` of the world origin (a length for positions, pure for normals).
    fn key_tolerance(&self, extent: f64) -> (f64, f64) {
        match &self.shape {
            Shape::Plane { point, offset, .. } => {
                let tn = self.normal_tolerance();
                let length = self.rounding.length
                    + POSITION_ROUNDING * point.abs().max_element()
                    + 2.0 * self.rounding.relative * offset
                    + 6.0 * tn * extent;
                (tn, length)
            }
            Shape::Curved { centre, unit } => {
                let length = self.rounding.length
                    + POSITION_ROUNDING * centre.abs().max_element()
                    + 2.0
                        * self.rounding.relative
                        * ((*centre - self.quadric.origin()).abs().max_element() + unit);
                (0.0, length)
            }
        }
    }

    /// The largest coordinate it involves.
    fn extent(&self) -> f64 {
        match &self.shape {
            Shape::Plane { point, offset, .. } => point.abs().max_element() + offset,
            Shape::Curved { centre, unit, .. } => centre.abs().max_element() + unit,
        }
    }
}

/// Appends the sheets of one quadric to `out`, from its principal frame (one
/// eigen-decomposition for all).
fn sheets_of<'a>(q: &'a Quadric, rounding: Rounding, out: &mut Vec<Candidate<'a>>) {
    let tolerances = Tolerances::default();
    let frame = PrincipalFrame::new(q, &tolerances);
    let candidate = |shape: Shape, one_sided: bool| Candidate {
        quadric: q,
        shape,
        one_sided,
        rounding,
    };
    let curved = || {
        let centre = centre_nearest_origin(q, &frame);
        candidate(
            Shape::Curved {
                centre,
                unit: q.length_unit(),
            },
            true,
        )
    };
    match classify_frame(&frame, &tolerances) {
        QuadricKind::Empty | QuadricKind::AllSpace => {}
        QuadricKind::Plane => out.push(match plane(q) {
            Some(shape) => candidate(shape, true),
            None => curved(),
        }),
        QuadricKind::ParallelPlanes => match slab_planes(q, &frame) {
            Some((low, high, one_sided)) => {
                out.push(candidate(low, one_sided));
                out.push(candidate(high, one_sided));
            }
            None => out.push(curved()),
        },
        _ => out.push(curved()),
    }
}

/// A plane sheet, when its point and normal are finite and the normal not zero.
fn plane_shape(normal: DVec3, point: DVec3, offset: f64) -> Option<Shape> {
    (normal.is_finite() && point.is_finite() && offset.is_finite() && normal != DVec3::ZERO)
        .then_some(Shape::Plane {
            normal,
            point,
            offset,
        })
}

/// The plane of a half-space `2 l·x + j ≤ 0` (its quadratic part is rounding noise or zero).
fn plane(q: &Quadric) -> Option<Shape> {
    let l = q.linear();
    let length = l.length();
    if !(length > 0.0 && length.is_finite()) {
        return None;
    }
    let normal = l / length;
    // 2 |l| s + j = 0 along the normal from the origin.
    let s = -q.constant() / (2.0 * length);
    plane_shape(normal, q.origin() + s * normal, s.abs())
}

/// The two planes of a slab `λ y² + κ ≤ 0` (or its complement) in its principal frame, and
/// whether the solid lies between them.
fn slab_planes(q: &Quadric, frame: &PrincipalFrame) -> Option<(Shape, Shape, bool)> {
    let mut axes = (0..3).filter(|&k| frame.eigenvalues[k] != 0.0);
    let k = axes.next()?;
    if axes.next().is_some() {
        return None;
    }
    let lambda = frame.eigenvalues[k];
    let half = (-frame.constant / lambda).sqrt();
    if !(half > 0.0 && half.is_finite()) {
        return None;
    }
    let axis = frame.axes[k];
    // The solid is between the planes when λ > 0: outward is away from the centre there.
    let out = if lambda > 0.0 { 1.0 } else { -1.0 };
    let offset = (frame.centre - q.origin()).abs().max_element() + half;
    let sheet =
        |side: f64| plane_shape(out * side * axis, frame.centre + side * half * axis, offset);
    Some((sheet(-1.0)?, sheet(1.0)?, lambda > 0.0))
}

/// The point of a quadric's centre set nearest the world origin, an invariant of its surface
/// (for quadrics without a centre, such as paraboloids, the same on the axes where `A` is not
/// null): on each principal axis `u` with `λ ≠ 0`, `u·p = u·origin − u·l / λ`.
fn centre_nearest_origin(q: &Quadric, frame: &PrincipalFrame) -> DVec3 {
    let (origin, l) = (q.origin(), q.linear());
    let mut centre = DVec3::ZERO;
    for (value, axis) in frame.eigenvalues.iter().zip(frame.axes.iter()) {
        if *value != 0.0 {
            centre += *axis * (axis.dot(origin) - axis.dot(l) / value);
        }
    }
    if centre.is_finite() { centre } else { origin }
}

/// Cell sizes of the hash grid: one for normals, one for lengths.
#[derive(Clone, Copy, Debug)]
struct Grid {
    normal: f64,
    length: f64,
    /// How far apart the keys of two matching sheets may lie: twice the largest tolerance.
    normal_reach: f64,
    length_reach: f64,
}

impl Grid {
    fn for_candidates(candidates: &[Candidate]) -> Self {
        let extent = candidates
            .iter()
            .map(Candidate::extent)
            .filter(|e| e.is_finite())
            .fold(0.0f64, f64::max);
        let (mut normal_reach, mut length_reach) = (0.0f64, 0.0f64);
        for candidate in candidates {
            let (n, l) = candidate.key_tolerance(extent);
            if n.is_finite() {
                normal_reach = normal_reach.max(2.0 * n);
            }
            if l.is_finite() {
                length_reach = length_reach.max(2.0 * l);
            }
        }
        Self {
            normal: CELL_FLOOR.max(4.0 * normal_reach),
            length: (extent * CELL_FLOOR)
                .max(4.0 * length_reach)
                .max(f64::MIN_POSITIVE),
            normal_reach,
            length_reach,
        }
    }
}

/// The cells to look in for a value whose matches lie within `reach` of it (`reach` at most
/// half the cell `width`): its own, and the neighbour on the nearer side when the value lies
/// within `reach` of that border (else its own again).
fn cells(value: f64, width: f64, reach: f64) -> [i64; 2] {
    let scaled = value / width;
    let home = scaled.floor();
    let (into_cell, reach) = (scaled - home, reach / width);
    let other = if into_cell <= reach {
        home - 1.0
    } else if 1.0 - into_cell <= reach {
        home + 1.0
    } else {
        home
    };
    [home as i64, other as i64]
}

/// All distinct combinations of the per-coordinate cells (home first).
fn probes<const N: usize>(cells: [[i64; 2]; N]) -> impl Iterator<Item = [i64; N]> {
    let split = (0..N).fold(0usize, |m, d| {
        m | usize::from(cells[d][0] != cells[d][1]) << d
    });
    (0..1usize << N)
        .filter(move |mask| mask & !split == 0)
        .map(move |mask| std::array::from_fn(|d| cells[d][(mask >> d) & 1]))
}

struct Finder<'c, 'a> {
    grid: Grid,
    candidates: &'c [Candidate<'a>],
    planes: HashMap<[i64; 4], Vec<u32>>,
    curved: HashMap<[i64; 3], Vec<u32>>,
    filed: Filed,
}

/// The surfaces found so far.
struct Filed {
    /// The first sheet of each surface (an index into the candidates).
    representatives: Vec<u32>,
    surfaces: Surfaces,
}

impl Finder<'_, '_> {
    /// The sheet of candidate `index`: an existing surface it matches, or a new one.
    fn file(&mut self, index: usize) -> Sheet {
        let candidate = &self.candidates[index];
        let (surface, orientation) = match &candidate.shape {
            Shape::Plane { normal, point, .. } => {
                let key = [
                    normal.x.abs(),
                    normal.y.abs(),
                    normal.z.abs(),
                    normal.dot(*point).abs(),
                ];
                let (n, l) = (self.grid.normal, self.grid.length);
                let (rn, rl) = (self.grid.normal_reach, self.grid.length_reach);
                let cells = [(n, rn), (n, rn), (n, rn), (l, rl)];
                self.filed
                    .find_or_file(self.candidates, index, key, cells, &mut self.planes)
            }
            Shape::Curved { centre, .. } => {
                let cells = [(self.grid.length, self.grid.length_reach); 3];
                self.filed.find_or_file(
                    self.candidates,
                    index,
                    centre.to_array(),
                    cells,
                    &mut self.curved,
                )
            }
        };
        Sheet {
            surface,
            orientation,
            one_sided: candidate.one_sided,
        }
    }
}

impl Filed {
    /// The surface of `candidates[index]` among those filed in `map` near `key` (cell size and
    /// reach per coordinate), or a new one filed there; with the candidate's orientation on it.
    fn find_or_file<const N: usize>(
        &mut self,
        candidates: &[Candidate],
        index: usize,
        key: [f64; N],
        grid: [(f64, f64); N],
        map: &mut HashMap<[i64; N], Vec<u32>>,
    ) -> (u32, i8) {
        let candidate = &candidates[index];
        let finite = key.iter().all(|k| k.is_finite());
        if finite {
            let around: [[i64; 2]; N] =
                std::array::from_fn(|d| cells(key[d], grid[d].0, grid[d].1));
            for probe in probes(around) {
                let Some(found) = map.get(&probe) else {
                    continue;
                };
                for &id in found.iter().take(MAX_CANDIDATES_PER_CELL) {
                    self.surfaces.comparisons += 1;
                    let first = &candidates[self.representatives[id as usize] as usize];
                    if let Some(orientation) = same_surface(first, candidate) {
                        self.surfaces.surfaces[id as usize].sheets += 1;
                        return (id, orientation);
                    }
                }
            }
        }
        let id = self.surfaces.surfaces.len() as u32;
        let (quadric, planar) = match &candidate.shape {
            // Finite point and non-zero finite normal: the half-space exists.
            Shape::Plane { normal, point, .. } => match Quadric::half_space(*point, *normal) {
                Some(half_space) => (half_space, true),
                None => (*candidate.quadric, false),
            },
            Shape::Curved { .. } => (*candidate.quadric, false),
        };
        self.surfaces.surfaces.push(Surface {
            quadric,
            planar,
            sheets: 1,
        });
        self.representatives.push(index as u32);
        if finite {
            let home: [i64; N] = std::array::from_fn(|d| (key[d] / grid[d].0).floor() as i64);
            map.entry(home).or_default().push(id);
        }
        (id, 1)
    }
}

/// The orientation of sheet `b` relative to sheet `a` if they are one surface.
fn same_surface(a: &Candidate, b: &Candidate) -> Option<i8> {
    match (&a.shape, &b.shape) {
        (Shape::Plane { .. }, Shape::Plane { .. }) => same_plane(a, b),
        (Shape::Curved { .. }, Shape::Curved { .. }) => same_curved(a, b),
        _ => None,
    }
}

/// The orientation of plane `b` relative to plane `a` if they are one surface.
fn same_plane(a: &Candidate, b: &Candidate) -> Option<i8> {
    let (
        Shape::Plane {
            normal: na,
            point: pa,
            offset: wa,
        },
        Shape::Plane {
            normal: nb,
            point: pb,
            offset: wb,
        },
    ) = (&a.shape, &b.shape)
    else {
        return None;
    };
    let sign = if na.dot(*nb) >= 0.0 { 1.0 } else { -1.0 };
    let tn = a.normal_tolerance() + b.normal_tolerance();
    if (*na - sign * *nb).abs().max_element() > tn {
        return None;
    }
    let apart = (*pb - *pa).abs().max_element();
    let tolerance = a.rounding.length
        + b.rounding.length
        + POSITION_ROUNDING * (pa.abs().max_element() + pb.abs().max_element())
        + 2.0 * (a.rounding.relative * wa + b.rounding.relative * wb)
        + 3.0 * tn * apart;
    let separation = na.dot(*pb - *pa).abs().max(nb.dot(*pa - *pb).abs());
    (separation <= tolerance).then_some(if sign > 0.0 { 1 } else { -1 })
}

/// The orientation of curved sheet `b` relative to `a` if they are one surface.
fn same_curved(a: &Candidate, b: &Candidate) -> Option<i8> {
    let Shape::Curved { unit, .. } = &a.shape else {
        return None;
    };
    let (qa, qb) = (a.quadric, b.quadric);
    let shift = qa.origin() - qb.origin();
    let moved = qb.with_origin(qa.origin());
    let balance = |k: [f64; 10]| {
        let mut out = k;
        out[..6].iter_mut().for_each(|c| *c *= unit * unit);
        out[6..9].iter_mut().for_each(|c| *c *= unit);
        out
    };
    let (ka, kb) = (balance(qa.coefficients()), balance(moved.coefficients()));
    let largest = |k: &[f64; 10]| k.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    let (ma, mb) = (largest(&ka), largest(&kb));
    if !(ma > 0.0 && mb > 0.0 && ma.is_finite() && mb.is_finite()) {
        return None;
    }
    let dot: f64 = ka.iter().zip(&kb).map(|(x, y)| x * y).sum();
    let sign = if dot >= 0.0 { 1.0 } else { -1.0 };
    let difference = ka
        .iter()
        .zip(&kb)
        .map(|(x, y)| (x / ma - sign * y / mb).abs())
        .fold(0.0f64, f64::max);
    // Re-expanding b about a's origin rounds its linear part and constant (see
    // `Quadric::with_origin` and `Quadric::value_with_error`).
    let k = qb.coefficients();
    let sum_a = k[0].abs() + k[1].abs() + k[2].abs() + 2.0 * (k[3].abs() + k[4].abs() + k[5].abs());
    let sum_l = k[6].abs() + k[7].abs() + k[8].abs();
    let s = shift.abs().max_element();
    let linear_error = 4.0 * U * (s * sum_a + sum_l) * unit;
    let constant_error = 16.0 * U * ((s * sum_a + 2.0 * sum_l) * s + k[9].abs());
    let moved_error = (linear_error + constant_error) / mb;
    let displacement = (a.rounding.length + b.rounding.length) / unit;
    let tolerance = 2.0 * (a.rounding.relative + b.rounding.relative)
        + 6.0 * displacement
        + 3.0 * displacement * displacement
        + moved_error
        + 8.0 * U;
    (difference <= tolerance).then_some(if sign > 0.0 { 1 } else { -1 })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn probes_cover_the_nearer_neighbour_within_reach() {
        assert_eq!(cells(0.2, 1.0, 0.25), [0, -1]);
        assert_eq!(cells(0.8, 1.0, 0.25), [0, 1]);
        assert_eq!(cells(0.5, 1.0, 0.25), [0, 0]);
        assert_eq!(cells(-0.1, 1.0, 0.25), [-1, 0]);
        let all: Vec<[i64; 2]> = probes([[0, -1], [5, 6]]).collect();
        assert_eq!(all, vec![[0, 5], [-1, 5], [0, 6], [-1, 6]]);
        let all: Vec<[i64; 2]> = probes([[0, -1], [5, 5]]).collect();
        assert_eq!(all, vec![[0, 5], [-1, 5]]);
    }
}
