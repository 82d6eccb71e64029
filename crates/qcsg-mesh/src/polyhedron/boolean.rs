//! Booleans of half-spaces as convex cells: a partition of a box by the expression's own planes,
//! with the expression simplified region by region.
//!
//! A solid built from half-spaces by unions and intersections (complements pushed to the leaves
//! by the caller, so a leaf is a half-space on one side of its plane) is, inside any box, a union
//! of convex cells, and so is its complement: the leaves of a binary space partition by its planes
//! on which the expression is constant. The partition here keeps, for each region, the expression
//! **reduced to that region**: a half-space that does not cut the region becomes true or false, a
//! node whose box misses the region becomes false (or true, for a node whose complement lies in a
//! box), and constants fold away. A region whose expression is constant is a leaf: a cell of the
//! solid or of its complement. Otherwise it is split by the plane of one of the half-spaces that
//! still cut it (in a fixed pseudo-random order), which takes that half-space out of both
//! children, so the partition always progresses; while a region's expression still holds many
//! half-spaces, or the region has many faces, it is halved by an axis-parallel plane instead, like
//! a kd-tree, so that far-apart parts of a large expression are separated by space before their
//! planes cut each other's regions.
//!
//! The cost follows the expression's reduced size summed over the regions, which is near-linear
//! when the solid's parts have boxes (the cells of a polygon or a mesh): a region only sees the
//! parts near it. Limits on cells and regions turn a blow-up into an error.
//!
//! **Unbounded boxes.** An axis along which the box is unbounded is allowed when no plane depends
//! on it (every normal has a zero component there, as for the z-invariant 2-D shapes): the
//! partition is then a prism along that axis, computed on a finite placeholder extent, and its
//! cells have no wall and an unbounded box along that axis.
//!
//! **Exactness.** Every face of a cell is one of the input planes (bit for bit, or its exact
//! negation), an axis-parallel wall of the box or a halving plane; the corners of the regions
//! are rounded and serve only to decide sides and boxes, as in the polyhedron's partition.

use glam::DVec3;

use super::region::Polytope;
use super::{Cell3, Plane};

/// A region whose expression still holds more half-spaces than this is halved by an
/// axis-parallel plane first, where that separates them.
const SPATIAL_LITERALS: usize = 24;

/// A region with more faces than this is halved by an axis-parallel plane first.
const MAX_FACES: usize = 12;

/// A box `[min, max]`.
pub type Bounds = (DVec3, DVec3);

/// What a node of a [`HalfSpaceExpr`] is.
#[derive(Clone, Debug, PartialEq)]
pub enum ExprKind {
    /// The half-space `planes[i]` (`normal · p ≤ offset`).
    HalfSpace(u32),
    /// The intersection of the children (none: everything).
    All(Vec<u32>),
    /// The union of the children (none: nothing).
    Any(Vec<u32>),
}

/// One node of a [`HalfSpaceExpr`], with the boxes known about it.
#[derive(Clone, Debug, PartialEq)]
pub struct ExprNode {
    /// What it is.
    pub kind: ExprKind,
    /// A box containing the node's solid, if known.
    pub inside: Option<Bounds>,
    /// A box containing the node's complement, if known (the complement of a bounded part).
    pub outside: Option<Bounds>,
}

/// A boolean of half-spaces: an arena in which children precede their parents.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HalfSpaceExpr {
    /// The nodes.
    pub nodes: Vec<ExprNode>,
    /// The node of the whole solid.
    pub root: u32,
}

/// Limits on the partition.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BooleanLimits {
    /// The most cells returned.
    pub max_cells: usize,
    /// The most regions examined.
    pub max_regions: usize,
}

/// Why a partition was not made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BooleanError {
    /// More cells than [`BooleanLimits::max_cells`].
    TooManyCells,
    /// More regions than [`BooleanLimits::max_regions`].
    TooManyRegions,
    /// The box is unbounded along an axis that some plane depends on (or is empty, or not
    /// finite where it is bounded).
    BadBox,
    /// A node refers to a plane or node that does not exist (or not to an earlier node).
    BadExpression,
}

/// The expression reduced to a region: a tree whose inner nodes remember the input node they
/// came from (for its boxes).
#[derive(Clone, Debug)]
enum Reduced {
    Literal(u32),
    All(u32, Vec<Reduced>),
    Any(u32, Vec<Reduced>),
}

/// A reduction's outcome.
enum Value {
    Constant(bool),
    Expr(Reduced),
}

/// A region awaiting its split.
struct Region {
    polytope: Polytope,
    expr: Reduced,
}

struct Partition<'a> {
    planes: &'a [Plane],
    nodes: &'a [ExprNode],
    magnitude: f64,
    /// Axes along which the box is unbounded (and the placeholder extent stands in).
    free: [bool; 3],
    min: DVec3,
    max: DVec3,
    want: bool,
    limits: BooleanLimits,
    cells: Vec<Cell3>,
    regions: usize,
}

/// The cells inside the box `[min, max]` on which `expr` is `want`: with `want = true` the solid
/// within the box, with `want = false` its complement within the box. Cells have disjoint
/// interiors. See the module's page for unbounded boxes.
pub fn boolean_cells(
    planes: &[Plane],
    expr: &HalfSpaceExpr,
    min: DVec3,
    max: DVec3,
    want: bool,
    limits: BooleanLimits,
) -> Result<Vec<Cell3>, BooleanError> {
    validate(planes, expr)?;
    let mut free = [false; 3];
    let (mut lo, mut hi) = (min, max);
    for axis in 0..3 {
        if min[axis].is_nan() || max[axis].is_nan() || min[axis] >= max[axis] {
            return Err(BooleanError::BadBox);
        }
        let (a, b) = (min[axis].is_finite(), max[axis].is_finite());
        if a && b {
            continue;
        }
        if planes.iter().any(|p| p.normal[axis] != 0.0) {
            return Err(BooleanError::BadBox);
        }
        free[axis] = true;
        (lo[axis], hi[axis]) = (-1.0, 1.0);
    }
    let magnitude = (0..3)
        .filter(|&a| !free[a])
        .map(|a| lo[a].abs().max(hi[a].abs()))
        .fold(0.0f64, f64::max);
    let mut partition = Partition {
        planes,
        nodes: &expr.nodes,
        magnitude,
        free,
        min,
        max,
        want,
        limits,
        cells: Vec::new(),
        regions: 0,
    };
    let polytope = Polytope::from_box(lo, hi);
    let whole = partition.initial(expr.root);
    match partition.reduce(&whole, &polytope) {
        Value::Constant(value) => {
            if value == want {
                partition.emit(polytope)?;
            }
        }
        Value::Expr(expr) => partition.run(Region { polytope, expr })?,
    }
    Ok(partition.cells)
}

fn validate(planes: &[Plane], expr: &HalfSpaceExpr) -> Result<(), BooleanError> {
    for (i, node) in expr.nodes.iter().enumerate() {
        let ok = match &node.kind {
            ExprKind::HalfSpace(p) => (*p as usize) < planes.len(),
            ExprKind::All(c) | ExprKind::Any(c) => c.iter().all(|&c| (c as usize) < i),
        };
        if !ok {
            return Err(BooleanError::BadExpression);
        }
    }
    if (expr.root as usize) >= expr.nodes.len() {
        return Err(BooleanError::BadExpression);
    }
    if planes
        .iter()
        .any(|p| !p.normal.is_finite() || !p.offset.is_finite() || p.normal == DVec3::ZERO)
    {
        return Err(BooleanError::BadExpression);
    }
    Ok(())
}

/// The order in which planes split: a fixed scramble of their indices.
fn priority(index: u32) -> u64 {
    let mut z = u64::from(index).wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Whether two boxes are disjoint (touching boxes meet: the solids are closed).
fn disjoint(a: &Bounds, b: &Bounds) -> bool {
    (0..3).any(|k| a.1[k] < b.0[k] || b.1[k] < a.0[k])
}

impl Partition<'_> {
    /// The rounding tolerance of `plane`'s values at points of this box's magnitude.
    fn tolerance(&self, plane: &Plane) -> f64 {
        let n = plane.normal.abs();
        64.0 * f64::EPSILON * ((n.x + n.y + n.z) * self.magnitude + plane.offset.abs())
    }

    /// The input expression as a tree (each node once per path: the caller's expression is a
    /// tree already, or small).
    fn initial(&self, id: u32) -> Reduced {
        stacker::maybe_grow(128 * 1024, 4 * 1024 * 1024, || {
            match &self.nodes[id as usize].kind {
                ExprKind::HalfSpace(p) => Reduced::Literal(*p),
                ExprKind::All(c) => Reduced::All(id, c.iter().map(|&c| self.initial(c)).collect()),
                ExprKind::Any(c) => Reduced::Any(id, c.iter().map(|&c| self.initial(c)).collect()),
            }
        })
    }

    /// The region's box, unbounded along the free axes.
    fn region_box(&self, polytope: &Polytope) -> Bounds {
        let (mut lo, mut hi) = polytope.bounds();
        for axis in 0..3 {
            if self.free[axis] {
                (lo[axis], hi[axis]) = (f64::NEG_INFINITY, f64::INFINITY);
            }
        }
        (lo, hi)
    }

    /// `expr` reduced to the region.
    fn reduce(&self, expr: &Reduced, polytope: &Polytope) -> Value {
        let corners: Vec<DVec3> = polytope.corners().collect();
        let bounds = self.region_box(polytope);
        self.reduce_in(expr, &corners, &bounds)
    }

    fn reduce_in(&self, expr: &Reduced, corners: &[DVec3], bounds: &Bounds) -> Value {
        stacker::maybe_grow(128 * 1024, 4 * 1024 * 1024, || match expr {
            Reduced::Literal(p) => {
                let plane = &self.planes[*p as usize];
                let tolerance = self.tolerance(plane);
                let (mut below, mut above) = (false, false);
                for &c in corners {
                    let v = plane.value(c);
                    below |= v < -tolerance;
                    above |= v > tolerance;
                }
                match (below, above) {
                    (true, true) => Value::Expr(expr.clone()),
                    // A region within rounding of the plane counts as inside (as the split does).
                    (_, false) => Value::Constant(true),
                    (false, true) => Value::Constant(false),
                }
            }
            Reduced::All(id, children) | Reduced::Any(id, children) => {
                let all = matches!(expr, Reduced::All(..));
                let node = &self.nodes[*id as usize];
                if node.inside.is_some_and(|b| disjoint(&b, bounds)) {
                    return Value::Constant(false);
                }
                if node.outside.is_some_and(|b| disjoint(&b, bounds)) {
                    return Value::Constant(true);
                }
                // All: a false child decides; Any: a true one.
                let decisive = !all;
                let mut kept = Vec::new();
                for child in children {
                    match self.reduce_in(child, corners, bounds) {
                        Value::Constant(v) if v == decisive => return Value::Constant(decisive),
                        Value::Constant(_) => {}
                        Value::Expr(e) => kept.push(e),
                    }
                }
                match kept.len() {
                    0 => Value::Constant(!decisive),
                    1 => Value::Expr(kept.pop().expect("one child")),
                    _ if all => Value::Expr(Reduced::All(*id, kept)),
                    _ => Value::Expr(Reduced::Any(*id, kept)),
                }
            }
        })
    }

    /// How many half-spaces the reduced expression holds (counted once per occurrence) and
    /// the plane of least priority among them.
    fn literals(&self, expr: &Reduced) -> (usize, u32) {
        let mut count = 0;
        let mut best: Option<u32> = None;
        let mut stack = vec![expr];
        while let Some(e) = stack.pop() {
            match e {
                Reduced::Literal(p) => {
                    count += 1;
                    if best.is_none_or(|b| priority(*p) < priority(b)) {
                        best = Some(*p);
                    }
                }
                Reduced::All(_, c) | Reduced::Any(_, c) => stack.extend(c.iter()),
            }
        }
        (count, best.unwrap_or(0))
    }

    fn emit(&mut self, polytope: Polytope) -> Result<(), BooleanError> {
        if self.cells.len() >= self.limits.max_cells {
            return Err(BooleanError::TooManyCells);
        }
        let pad = 1e-12 * self.magnitude.max(f64::MIN_POSITIVE);
        let mut cell = polytope.into_cell(pad, self.min, self.max);
        if self.free.iter().any(|&f| f) {
            // The placeholder's walls along a free axis bound nothing.
            let free = self.free;
            cell.planes.retain(|p| {
                !(0..3).any(|axis| {
                    free[axis] && p.normal[axis] != 0.0 && {
                        let mut rest = p.normal;
                        rest[axis] = 0.0;
                        rest == DVec3::ZERO
                    }
                })
            });
            for (axis, _) in free.iter().enumerate().filter(|(_, f)| **f) {
                (cell.min[axis], cell.max[axis]) = (self.min[axis], self.max[axis]);
            }
        }
        self.cells.push(cell);
        Ok(())
    }

    /// An axis-parallel plane through the middle of the region's longest bounded extent.
    fn halving_plane(&self, polytope: &Polytope) -> Option<Plane> {
        let (lo, hi) = polytope.bounds();
        let axis = (0..3)
            .filter(|&a| !self.free[a])
            .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))?;
        let mut normal = DVec3::ZERO;
        normal[axis] = 1.0;
        Some(Plane {
            normal,
            offset: 0.5 * (lo[axis] + hi[axis]),
        })
    }

    fn run(&mut self, root: Region) -> Result<(), BooleanError> {
        let mut stack = vec![root];
        while let Some(region) = stack.pop() {
            self.regions += 1;
            if self.regions > self.limits.max_regions {
                return Err(BooleanError::TooManyRegions);
            }
            let (count, splitter) = self.literals(&region.expr);
            let many_faces = region.polytope.face_count() > MAX_FACES;
            if (count > SPATIAL_LITERALS || many_faces)
                && let Some(plane) = self.halving_plane(&region.polytope)
                && let Some((low, high)) = region.polytope.split(plane, self.tolerance(&plane))
            {
                let parts = [low, high].map(|p| {
                    let value = self.reduce(&region.expr, &p);
                    (p, value)
                });
                // Kept where it separates the planes (or the region had too many faces):
                // planes through one point (a fan) reach both halves however small.
                let fewer = |v: &Value| match v {
                    Value::Constant(_) => true,
                    Value::Expr(e) => self.literals(e).0 < count,
                };
                if many_faces || parts.iter().all(|(_, v)| fewer(v)) {
                    for (polytope, value) in parts {
                        self.settle(polytope, value, &mut stack)?;
                    }
                    continue;
                }
            }
            let plane = self.planes[splitter as usize];
            let Some((low, high)) = region.polytope.split(plane, self.tolerance(&plane)) else {
                // Every remaining plane is within rounding of the region: decide it by its
                // centre (a sliver below the rounding of the corners).
                let centre = region.polytope.interior_point();
                if self.value_at(&region.expr, centre) == self.want {
                    self.emit(region.polytope)?;
                }
                continue;
            };
            for polytope in [low, high] {
                let value = self.reduce(&region.expr, &polytope);
                self.settle(polytope, value, &mut stack)?;
            }
        }
        Ok(())
    }

    /// A cell where the reduced expression is constant, else a region to split further.
    fn settle(
        &mut self,
        polytope: Polytope,
        value: Value,
        stack: &mut Vec<Region>,
    ) -> Result<(), BooleanError> {
        match value {
            Value::Constant(value) => {
                if value == self.want {
                    self.emit(polytope)?;
                }
            }
            Value::Expr(expr) => stack.push(Region { polytope, expr }),
        }
        Ok(())
    }

    /// The expression's value at a point.
    fn value_at(&self, expr: &Reduced, p: DVec3) -> bool {
        match expr {
            Reduced::Literal(i) => self.planes[*i as usize].contains(p),
            Reduced::All(_, c) => c.iter().all(|e| self.value_at(e, p)),
            Reduced::Any(_, c) => c.iter().any(|e| self.value_at(e, p)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIMITS: BooleanLimits = BooleanLimits {
        max_cells: 100_000,
        max_regions: 1_000_000,
    };

    fn leaf(nodes: &mut Vec<ExprNode>, kind: ExprKind, inside: Option<Bounds>) -> u32 {
        nodes.push(ExprNode {
            kind,
            inside,
            outside: None,
        });
        nodes.len() as u32 - 1
    }

    /// A unit-cube grid of `n` × `n` cubes in a checkerboard, as boxed intersections of six
    /// half-spaces each, united.
    fn checkerboard(n: usize) -> (Vec<Plane>, HalfSpaceExpr) {
        let mut planes = Vec::new();
        let mut nodes = Vec::new();
        let mut cubes = Vec::new();
        for i in 0..n {
            for j in 0..n {
                if (i + j) % 2 == 1 {
                    continue;
                }
                let lo = DVec3::new(i as f64, j as f64, 0.0);
                let hi = lo + DVec3::ONE;
                let mut sides = Vec::new();
                for axis in 0..3 {
                    let mut normal = DVec3::ZERO;
                    normal[axis] = 1.0;
                    for (normal, offset) in [(normal, hi[axis]), (-normal, -lo[axis])] {
                        planes.push(Plane { normal, offset });
                        let p = planes.len() as u32 - 1;
                        sides.push(leaf(&mut nodes, ExprKind::HalfSpace(p), None));
                    }
                }
                cubes.push(leaf(&mut nodes, ExprKind::All(sides), Some((lo, hi))));
            }
        }
        let root = leaf(&mut nodes, ExprKind::Any(cubes), None);
        (planes, HalfSpaceExpr { nodes, root })
    }

    fn inside(cells: &[Cell3], p: DVec3) -> bool {
        cells.iter().any(|c| c.contains(p))
    }

    #[test]
    fn a_union_and_its_complement_tile_the_box() {
        let n = 12;
        let (planes, expr) = checkerboard(n);
        let (min, max) = (DVec3::splat(-1.0), DVec3::splat(n as f64 + 1.0));
        let solid = boolean_cells(&planes, &expr, min, max, true, LIMITS).unwrap();
        let rest = boolean_cells(&planes, &expr, min, max, false, LIMITS).unwrap();
        let mut state = 1u64;
        for _ in 0..4000 {
            let mut next = || {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (state >> 11) as f64 / (1u64 << 53) as f64
            };
            let p = min + (max - min) * DVec3::new(next(), next(), next());
            let (i, j) = (p.x.floor(), p.y.floor());
            let expected = (0.0..n as f64).contains(&p.x)
                && (0.0..n as f64).contains(&p.y)
                && (0.0..1.0).contains(&p.z)
                && (i + j) as i64 % 2 == 0;
            assert_eq!(inside(&solid, p), expected, "{p}");
            assert_eq!(inside(&rest, p), !expected, "{p}");
        }
        // Boxed parts keep the partition near-linear: a few cells per cube.
        let cubes = n * n / 2;
        assert!(solid.len() <= 4 * cubes, "{} cells", solid.len());
        assert!(rest.len() <= 8 * cubes, "{} cells", rest.len());
        for cell in solid.iter().chain(&rest) {
            assert!(cell.planes.len() <= MAX_FACES, "{:?}", cell.planes);
        }
    }

    #[test]
    fn faces_are_input_planes_or_axis_parallel() {
        let (planes, expr) = checkerboard(4);
        let cells = boolean_cells(
            &planes,
            &expr,
            DVec3::splat(-1.0),
            DVec3::splat(5.0),
            false,
            LIMITS,
        )
        .unwrap();
        for cell in &cells {
            for p in &cell.planes {
                let input = planes.iter().any(|q| q == p || q.flipped() == *p);
                let axis = p.normal.abs().max_element() == p.normal.length();
                assert!(input || axis, "{p:?}");
            }
        }
    }

    #[test]
    fn prisms_along_an_unbounded_axis() {
        // A square column minus a triangle, both z-invariant.
        let planes = vec![
            Plane {
                normal: DVec3::X,
                offset: 1.0,
            },
            Plane {
                normal: DVec3::NEG_X,
                offset: 1.0,
            },
            Plane {
                normal: DVec3::Y,
                offset: 1.0,
            },
            Plane {
                normal: DVec3::NEG_Y,
                offset: 1.0,
            },
            Plane {
                normal: DVec3::new(1.0, 1.0, 0.0),
                offset: 0.5,
            },
        ];
        let mut nodes = Vec::new();
        let sides: Vec<u32> = (0..5)
            .map(|p| leaf(&mut nodes, ExprKind::HalfSpace(p), None))
            .collect();
        let root = leaf(&mut nodes, ExprKind::All(sides), None);
        let expr = HalfSpaceExpr { nodes, root };
        let min = DVec3::new(-2.0, -2.0, f64::NEG_INFINITY);
        let max = DVec3::new(2.0, 2.0, f64::INFINITY);
        let cells = boolean_cells(&planes, &expr, min, max, true, LIMITS).unwrap();
        for z in [-1e9, 0.0, 3.5e7] {
            assert!(inside(&cells, DVec3::new(-0.9, -0.9, z)));
            assert!(!inside(&cells, DVec3::new(0.9, 0.9, z)));
        }
        assert!(cells.iter().all(|c| c.min.z == f64::NEG_INFINITY));
        // A tilted plane needs the box bounded.
        let mut tilted = planes.clone();
        tilted[4].normal.z = 0.1;
        assert_eq!(
            boolean_cells(&tilted, &expr, min, max, true, LIMITS),
            Err(BooleanError::BadBox)
        );
    }

    #[test]
    fn limits_are_errors() {
        let (planes, expr) = checkerboard(8);
        let limits = BooleanLimits {
            max_cells: 5,
            max_regions: 1_000_000,
        };
        let (min, max) = (DVec3::splat(-1.0), DVec3::splat(9.0));
        assert_eq!(
            boolean_cells(&planes, &expr, min, max, true, limits),
            Err(BooleanError::TooManyCells)
        );
        let limits = BooleanLimits {
            max_cells: 100_000,
            max_regions: 10,
        };
        assert_eq!(
            boolean_cells(&planes, &expr, min, max, true, limits),
            Err(BooleanError::TooManyRegions)
        );
    }
}
