//! Classification of quadrics into their kinds, from the signs of the canonical form
//! (see [`crate::frame`]) under scale-relative tolerances.

use crate::frame::{PrincipalFrame, Tolerances};
use crate::quadric::Quadric;

/// The kind of a quadric's surface. Kinds name the surface; which side is solid follows from the
/// coefficients' sign (a negated quadric has the same kind, apart from `Empty` ↔ `AllSpace`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum QuadricKind {
    /// No surface, and no point is inside.
    Empty,
    /// No surface, and every point is inside (also the all-zero quadric).
    AllSpace,
    /// An ellipsoid with three equal radii.
    Sphere,
    /// An ellipsoid with exactly two equal radii.
    Spheroid,
    /// An ellipsoid with three different radii.
    Ellipsoid,
    /// A single point (an ellipsoid of radius zero).
    Point,
    /// An elliptic (or circular) cylinder.
    EllipticCylinder,
    /// A hyperbolic cylinder.
    HyperbolicCylinder,
    /// A parabolic cylinder.
    ParabolicCylinder,
    /// A single line (an elliptic cylinder of radius zero).
    Line,
    /// An elliptic double cone.
    Cone,
    /// A hyperboloid of one sheet.
    HyperboloidOneSheet,
    /// A hyperboloid of two sheets.
    HyperboloidTwoSheets,
    /// An elliptic paraboloid.
    EllipticParaboloid,
    /// A hyperbolic paraboloid (saddle).
    HyperbolicParaboloid,
    /// A single plane (a half-space solid).
    Plane,
    /// Two parallel planes (a slab or its complement).
    ParallelPlanes,
    /// Two intersecting planes.
    IntersectingPlanes,
    /// A plane counted twice (`(n·x)² = 0`).
    CoincidentPlanes,
}

impl QuadricKind {
    /// Every kind, in declaration order.
    pub const ALL: [QuadricKind; 19] = [
        Self::Empty,
        Self::AllSpace,
        Self::Sphere,
        Self::Spheroid,
        Self::Ellipsoid,
        Self::Point,
        Self::EllipticCylinder,
        Self::HyperbolicCylinder,
        Self::ParabolicCylinder,
        Self::Line,
        Self::Cone,
        Self::HyperboloidOneSheet,
        Self::HyperboloidTwoSheets,
        Self::EllipticParaboloid,
        Self::HyperbolicParaboloid,
        Self::Plane,
        Self::ParallelPlanes,
        Self::IntersectingPlanes,
        Self::CoincidentPlanes,
    ];

    /// A stable lower-case name, used in JSON output.
    pub fn name(self) -> &'static str {
        match self {
            Self::Empty => "empty",
            Self::AllSpace => "all_space",
            Self::Sphere => "sphere",
            Self::Spheroid => "spheroid",
            Self::Ellipsoid => "ellipsoid",
            Self::Point => "point",
            Self::EllipticCylinder => "elliptic_cylinder",
            Self::HyperbolicCylinder => "hyperbolic_cylinder",
            Self::ParabolicCylinder => "parabolic_cylinder",
            Self::Line => "line",
            Self::Cone => "cone",
            Self::HyperboloidOneSheet => "hyperboloid_one_sheet",
            Self::HyperboloidTwoSheets => "hyperboloid_two_sheets",
            Self::EllipticParaboloid => "elliptic_paraboloid",
            Self::HyperbolicParaboloid => "hyperbolic_paraboloid",
            Self::Plane => "plane",
            Self::ParallelPlanes => "slab",
            Self::IntersectingPlanes => "intersecting_planes",
            Self::CoincidentPlanes => "coincident_planes",
        }
    }

    /// The kind with the given [`Self::name`].
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Sphere, spheroid or ellipsoid.
    pub fn is_ellipsoidal(self) -> bool {
        matches!(self, Self::Sphere | Self::Spheroid | Self::Ellipsoid)
    }

    /// Whether the surface is empty (no point has `Q = 0`).
    pub fn has_no_surface(self) -> bool {
        matches!(self, Self::Empty | Self::AllSpace)
    }
}

impl std::fmt::Display for QuadricKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The kind of a quadric given its principal frame.
pub fn classify_frame(frame: &PrincipalFrame, tolerances: &Tolerances) -> QuadricKind {
    use QuadricKind as K;
    let positive = frame.eigenvalues.iter().filter(|v| **v > 0.0).count();
    let negative = frame.eigenvalues.iter().filter(|v| **v < 0.0).count();
    let has_linear = frame.linear.iter().any(|m| *m != 0.0);
    // Orient so that positive eigenvalues are the majority; κ flips with the quadric.
    let (p, n, kappa) = if negative > positive {
        (negative, positive, -frame.constant)
    } else {
        (positive, negative, frame.constant)
    };
    let rank = p + n;
    // The sign that the quadric takes away from its surface when it has no surface, or is
    // degenerate: used to tell Empty from AllSpace.
    let no_surface = |sign_of_q_everywhere: f64| {
        if sign_of_q_everywhere > 0.0 {
            K::Empty
        } else {
            K::AllSpace
        }
    };
    let definite_sign = if negative > positive { -1.0 } else { 1.0 };
    use std::cmp::Ordering::{Equal, Greater, Less};
    let kappa_sign = if kappa == 0.0 {
        Equal
    } else if kappa < 0.0 {
        Less
    } else {
        Greater
    };
    match (rank, has_linear) {
        (3, _) => match (p, kappa_sign) {
            (3, Less) => ellipsoid_kind(frame, tolerances),
            (3, Equal) => K::Point,
            (3, Greater) => no_surface(definite_sign),
            (_, Equal) => K::Cone,
            (_, Less) => K::HyperboloidOneSheet,
            (_, Greater) => K::HyperboloidTwoSheets,
        },
        (2, true) => {
            if n == 0 {
                K::EllipticParaboloid
            } else {
                K::HyperbolicParaboloid
            }
        }
        (2, false) => match (p, kappa_sign) {
            (2, Less) => K::EllipticCylinder,
            (2, Equal) => K::Line,
            (2, Greater) => no_surface(definite_sign),
            (_, Equal) => K::IntersectingPlanes,
            _ => K::HyperbolicCylinder,
        },
        (1, true) => K::ParabolicCylinder,
        (1, false) => match kappa_sign {
            Less => K::ParallelPlanes,
            Equal => K::CoincidentPlanes,
            Greater => no_surface(definite_sign),
        },
        (_, true) => K::Plane,
        (_, false) => {
            if frame.constant > 0.0 {
                K::Empty
            } else {
                K::AllSpace
            }
        }
    }
}

fn ellipsoid_kind(frame: &PrincipalFrame, tolerances: &Tolerances) -> QuadricKind {
    let [a, b, c] = frame.eigenvalues;
    let largest = a.abs().max(b.abs()).max(c.abs());
    let equal = |x: f64, y: f64| (x - y).abs() <= tolerances.equal * largest;
    let pairs = [equal(a, b), equal(a, c), equal(b, c)]
        .iter()
        .filter(|e| **e)
        .count();
    match pairs {
        0 => QuadricKind::Ellipsoid,
        1 => QuadricKind::Spheroid,
        _ => QuadricKind::Sphere,
    }
}

impl Quadric {
    /// The kind of this quadric under default [`Tolerances`].
    pub fn kind(&self) -> QuadricKind {
        self.kind_with(&Tolerances::default())
    }

    /// The kind of this quadric under the given tolerances.
    pub fn kind_with(&self, tolerances: &Tolerances) -> QuadricKind {
        classify_frame(&PrincipalFrame::new(self, tolerances), tolerances)
    }
}
