//! Exact, numerically stable f64 quadric math (paper 000 §3).
//!
//! A [`Quadric`] is ten coefficients about a local origin; the solid is `q(p − origin) ≤ 0`.
//! This crate provides evaluation, gradients and normals, transforms (eq. 17) that keep the
//! coefficients well-conditioned, classification ([`QuadricKind`]), the principal frame
//! ([`PrincipalFrame`]: centre and axes from a robust symmetric eigen-decomposition), the
//! sampling-plane heightfields and their distortion bounds ([`Heightfield`]), the conservative
//! signed distance of eqs. 10-12 and line intersection ([`LineIntersection`]).
//!
//! Everything is f64, tolerances are relative to the coefficients' own scale, and no function
//! panics on finite input. Each function documents its error bound; the tests (notably
//! `tests/stiff.rs`) enforce them on extreme radii, translations, aspect ratios and near-degenerate
//! quadrics.
//!
//! ```
//! use qcsg_quadric::{DMat4, DVec3, Quadric, QuadricKind};
//!
//! // A unit sphere moved far away keeps its coefficients: only the origin moves.
//! let sphere = Quadric::sphere(DVec3::ZERO, 1.0).unwrap();
//! let far = sphere.transformed(&DMat4::from_translation(DVec3::splat(1e6))).unwrap();
//! assert_eq!(far.coefficients(), sphere.coefficients());
//! assert_eq!(far.kind(), QuadricKind::Sphere);
//!
//! // |d| never exceeds the true distance (here 1.0: the point is 2 from the centre).
//! let d = far.conservative_distance(DVec3::splat(1e6) + DVec3::new(2.0, 0.0, 0.0));
//! assert!(d > 0.0 && d <= 1.0);
//! ```

mod classify;
mod distance;
pub mod eigen;
mod frame;
mod heightfield;
mod intersect;
mod primitives;
mod quadric;

pub use classify::{QuadricKind, classify_frame};
pub use eigen::{SymmetricEigen, symmetric_eigen};
pub use frame::{PrincipalFrame, Tolerances};
pub use heightfield::{Heightfield, HeightfieldForm};
pub use intersect::LineIntersection;
pub use quadric::Quadric;

/// Re-export of the vector and matrix types used in the API.
pub use glam::{DMat4, DVec3};
