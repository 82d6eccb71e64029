//! DXF drawings with OpenSCAD 2021.01's meaning: the ENTITIES section (and BLOCKS for INSERT)
//! read as lines, arcs, circles and ellipses, joined end to end into paths.
//!
//! The file is a sequence of pairs of lines, a group code and its value; code 0 starts an entity,
//! which ends at the next code 0. What OpenSCAD reads: LINE, LWPOLYLINE (closed by flag 1),
//! CIRCLE, ARC, ELLIPSE, INSERT of a BLOCK (insertion point, x/y scale, rotation), and DIMENSION
//! (for `dxf_dim`). POLYLINE with its VERTEX entities is read too (closed by flag 1), which
//! OpenSCAD 2021.01 skips. Other entities in the selected layer or in a block are skipped with a
//! warning, as OpenSCAD does.
//!
//! Where OpenSCAD 2021.01 misreads what the format means, the drawing is read as the format means
//! it and a warning says how OpenSCAD differs: a polyline vertex's bulge (code 42) makes the edge
//! after it a circular arc (OpenSCAD draws the chord), and an ELLIPSE's major axis (codes 11/21,
//! relative to its centre) and axis ratio (code 40) are not shifted by `origin` nor the ratio
//! multiplied by `scale` (OpenSCAD does both).
//!
//! `origin` and `scale` apply as OpenSCAD applies them: `(p − origin) · scale` for entity points,
//! block contents untouched until an INSERT maps them by `R(rotation) · diag(sx, sy) · scale`
//! plus the insertion point. A layer name selects the entities of that layer (INSERTs by their
//! own layer); no name reads every layer.
//!
//! Curves stay exact: an arc is an edge with its centre and radius, an elliptic arc an edge with
//! its ellipse ([`EllipticArc`]), a full circle a [`DrawingCircle`], a full ellipse a
//! [`DrawingEllipse`]; nothing is tessellated. An INSERT that scales a block unevenly turns its
//! circles and arcs into ellipses and elliptic arcs, exactly. Joining ([`join`]) follows OpenSCAD's walk and its
//! tolerance for equal end points.

mod join;
mod parse;

use std::fmt;

use glam::DVec2;

pub use parse::read_dxf;

/// Limits on what a drawing may hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DrawingLimits {
    /// The most entities read, INSERTs expanded (default 1,000,000).
    pub max_entities: usize,
    /// The most edge end points in the result (default 10,000,000).
    pub max_points: usize,
}

impl Default for DrawingLimits {
    fn default() -> Self {
        Self {
            max_entities: 1_000_000,
            max_points: 10_000_000,
        }
    }
}

/// How `import` reads a drawing: which layer, and the map applied to its points.
#[derive(Clone, Debug, PartialEq)]
pub struct DrawingOptions {
    /// The layer read; `None` (or OpenSCAD's empty name) reads all layers.
    pub layer: Option<String>,
    /// Subtracted from every point before scaling.
    pub origin: DVec2,
    /// Multiplies every coordinate and radius.
    pub scale: f64,
}

impl Default for DrawingOptions {
    fn default() -> Self {
        Self {
            layer: None,
            origin: DVec2::ZERO,
            scale: 1.0,
        }
    }
}

/// The circle an arc edge follows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arc {
    /// The centre.
    pub center: DVec2,
    /// The radius (positive).
    pub radius: f64,
    /// Whether the arc turns counter-clockwise from the edge's `from` to its `to`.
    pub ccw: bool,
}

impl Arc {
    /// A point in the middle of the arc from `from` to `to`.
    pub fn midpoint(&self, from: DVec2, to: DVec2) -> DVec2 {
        let a0 = (from - self.center).to_angle();
        let mut a1 = (to - self.center).to_angle();
        if self.ccw {
            while a1 <= a0 {
                a1 += std::f64::consts::TAU;
            }
        } else {
            while a1 >= a0 {
                a1 -= std::f64::consts::TAU;
            }
        }
        self.center + DVec2::from_angle(0.5 * (a0 + a1)) * self.radius
    }
}

/// The ellipse an elliptic arc edge follows: the points `center + axes[0] cos t + axes[1] sin t`
/// (conjugate semi-diameters; the semi-axes for an ELLIPSE as drawn, any pair once an INSERT has
/// mapped it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EllipticArc {
    /// The centre.
    pub center: DVec2,
    /// The two conjugate semi-diameters (linearly independent).
    pub axes: [DVec2; 2],
    /// Whether the parameter `t` increases from the edge's `from` to its `to`.
    pub forward: bool,
}

impl EllipticArc {
    /// The point of parameter `t`.
    pub fn point(&self, t: f64) -> DVec2 {
        let (s, c) = t.sin_cos();
        self.center + self.axes[0] * c + self.axes[1] * s
    }

    /// The parameter of a point on the ellipse (its angle in the frame of the semi-diameters).
    pub fn param(&self, p: DVec2) -> f64 {
        let [a, b] = self.axes;
        let det = a.perp_dot(b);
        let d = p - self.center;
        // The coordinates of `d` in the basis (a, b), by Cramer's rule.
        let (x, y) = (d.perp_dot(b) / det, a.perp_dot(d) / det);
        y.atan2(x)
    }

    /// A point in the middle of the arc from `from` to `to`.
    pub fn midpoint(&self, from: DVec2, to: DVec2) -> DVec2 {
        let t0 = self.param(from);
        let sweep = (self.param(to) - t0).rem_euclid(std::f64::consts::TAU);
        let sweep = if sweep == 0.0 {
            std::f64::consts::TAU
        } else {
            sweep
        };
        if self.forward {
            self.point(t0 + 0.5 * sweep)
        } else {
            self.point(t0 - 0.5 * (std::f64::consts::TAU - sweep))
        }
    }
}

/// One edge of a path: a straight segment, a circular arc when `arc` is set, an elliptic arc
/// when `ellipse` is set (never both).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Edge {
    /// Where the edge starts.
    pub from: DVec2,
    /// Where the edge ends.
    pub to: DVec2,
    /// The circle it follows, for an arc.
    pub arc: Option<Arc>,
    /// The ellipse it follows, for an elliptic arc.
    pub ellipse: Option<EllipticArc>,
    /// The DXF line of the entity it comes from (0 for an edge that closes an open path).
    pub line: usize,
}

/// A closed outline: each edge ends where the next starts, the last where the first starts.
#[derive(Clone, Debug, PartialEq)]
pub struct DrawingPath {
    /// The edges in order.
    pub edges: Vec<Edge>,
    /// Whether the entities closed it; an open chain is closed by a straight edge, as OpenSCAD
    /// closes it, and reported in [`Drawing::warnings`].
    pub closed_in_file: bool,
}

/// A full circle (CIRCLE, or an ARC of 360°).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawingCircle {
    /// The centre.
    pub center: DVec2,
    /// The radius.
    pub radius: f64,
    /// The DXF line of its entity.
    pub line: usize,
}

/// A full ellipse (an ELLIPSE of a whole turn, or a circle scaled unevenly by an INSERT).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawingEllipse {
    /// The centre.
    pub center: DVec2,
    /// Two conjugate semi-diameters (see [`EllipticArc`]).
    pub axes: [DVec2; 2],
    /// The DXF line of its entity.
    pub line: usize,
}

/// A curve the reader keeps but qcsg cannot make a region of exactly (a circle or ellipse that
/// an INSERT of zero scale flattens to a line).
#[derive(Clone, Debug, PartialEq)]
pub struct DrawingCurve {
    /// The entity ("ELLIPSE", "CIRCLE in an unevenly scaled INSERT").
    pub entity: String,
    /// The DXF line of its entity.
    pub line: usize,
}

/// A DIMENSION entity, read for `dxf_dim`.
#[derive(Clone, Debug, PartialEq)]
pub struct Dimension {
    /// Its name (group code 1).
    pub name: String,
    /// Its type (group code 70).
    pub kind: i64,
    /// The points of codes 10–16 / 20–26 (origin and scale applied as OpenSCAD applies them).
    pub coords: [DVec2; 7],
    /// The angle (code 50), in degrees.
    pub angle: f64,
}

/// Something worth telling the user that does not stop the drawing.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum DrawingWarning {
    /// A chain of edges that does not close; it is closed by a straight edge, as OpenSCAD does.
    OpenPath {
        /// The DXF line of its first entity.
        line: usize,
    },
    /// Polyline vertices with a bulge: qcsg draws the arcs, OpenSCAD 2021.01 their chords.
    Bulges {
        /// How many edges are arcs by their bulge.
        count: usize,
        /// The DXF line of the first polyline with one.
        line: usize,
    },
    /// An ELLIPSE read with an `origin` or `scale`, which OpenSCAD 2021.01 also applies to the
    /// major axis's direction vector and the axis ratio.
    EllipseOptions {
        /// The DXF line of the first ELLIPSE.
        line: usize,
    },
    /// Entities OpenSCAD does not read, skipped.
    Unsupported {
        /// The entity's name.
        entity: String,
        /// How many were skipped.
        count: usize,
        /// The DXF line of the first.
        line: usize,
    },
}

impl fmt::Display for DrawingWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::OpenPath { line } => write!(
                f,
                "the path starting at DXF line {line} is open; it is closed by a straight edge"
            ),
            Self::Bulges { count, line } => write!(
                f,
                "{count} polyline edge{} with a bulge (first at DXF line {line}) drawn as circular \
                 arcs, as DXF means them; OpenSCAD 2021.01 draws their straight chords",
                if *count == 1 { "" } else { "s" }
            ),
            Self::EllipseOptions { line } => write!(
                f,
                "the ELLIPSE at DXF line {line} is moved by `origin` and scaled by `scale` as a \
                 whole; OpenSCAD 2021.01 also shifts its axis vector by `origin` and multiplies its \
                 axis ratio by `scale`, so its shape differs there"
            ),
            Self::Unsupported {
                entity,
                count,
                line,
            } => write!(
                f,
                "{count} unsupported DXF entit{} `{entity}` (first at line {line}) skipped",
                if *count == 1 { "y" } else { "ies" }
            ),
        }
    }
}

/// A drawing read from a DXF file: closed paths, full circles, and what qcsg keeps aside.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Drawing {
    /// The closed outlines (open chains closed).
    pub paths: Vec<DrawingPath>,
    /// The full circles.
    pub circles: Vec<DrawingCircle>,
    /// The full ellipses.
    pub ellipses: Vec<DrawingEllipse>,
    /// Curves read but not representable exactly yet.
    pub curves: Vec<DrawingCurve>,
    /// The DIMENSION entities of the selected layer.
    pub dimensions: Vec<Dimension>,
    /// Warnings.
    pub warnings: Vec<DrawingWarning>,
    /// The chains with exactly two points (single straight edges that join nothing), before
    /// closing: `dxf_cross` intersects the first two.
    pub(crate) two_point_chains: Vec<[DVec2; 2]>,
}

impl Drawing {
    /// OpenSCAD's `dxf_dim`: the measure of the first dimension named `name` (any when `None`):
    /// `Ok(None)` when there is none, `Err(kind)` when its type is one OpenSCAD does not measure.
    pub fn dimension(&self, name: Option<&str>) -> Result<Option<f64>, i64> {
        let Some(d) = self
            .dimensions
            .iter()
            .find(|d| name.is_none_or(|n| n.is_empty() || d.name == n))
        else {
            return Ok(None);
        };
        let c = &d.coords;
        let value = match d.kind & 7 {
            0 => {
                let v = c[4] - c[3];
                let (s, co) = degrees_sin_cos(d.angle);
                (v.x * co + v.y * s).abs()
            }
            1 => (c[4] - c[3]).length(),
            2 => {
                // OpenSCAD passes (x, y) to atan2 in this order; the difference is what counts.
                let a1 = (c[0].x - c[5].x).atan2(c[0].y - c[5].y).to_degrees();
                let a2 = (c[4].x - c[3].x).atan2(c[4].y - c[3].y).to_degrees();
                (a1 - a2).abs()
            }
            3 | 4 => (c[5] - c[0]).length(),
            6 => {
                if d.kind & 64 != 0 {
                    c[3].x
                } else {
                    c[3].y
                }
            }
            _ => return Err(d.kind),
        };
        Ok(Some(value))
    }

    /// OpenSCAD's `dxf_cross`: where the lines of the first two single-edge paths cross, or
    /// `None` when there are not two or they are parallel.
    pub fn cross(&self) -> Option<DVec2> {
        let [[p1, p2], [p3, p4]] = [
            *self.two_point_chains.first()?,
            *self.two_point_chains.get(1)?,
        ];
        let d = (p4.y - p3.y) * (p2.x - p1.x) - (p4.x - p3.x) * (p2.y - p1.y);
        if d == 0.0 {
            return None;
        }
        let ua = ((p4.x - p3.x) * (p1.y - p3.y) - (p4.y - p3.y) * (p1.x - p3.x)) / d;
        Some(p1 + (p2 - p1) * ua)
    }
}

/// `(sin, cos)` of an angle in degrees, exact at multiples of 90° (as OpenSCAD's
/// `sin_degrees`/`cos_degrees`), so axis-aligned arcs end exactly on the axes.
pub(crate) fn degrees_sin_cos(degrees: f64) -> (f64, f64) {
    let reduced = degrees.rem_euclid(360.0);
    if reduced == 0.0 {
        (0.0, 1.0)
    } else if reduced == 90.0 {
        (1.0, 0.0)
    } else if reduced == 180.0 {
        (0.0, -1.0)
    } else if reduced == 270.0 {
        (-1.0, 0.0)
    } else {
        reduced.to_radians().sin_cos()
    }
}
