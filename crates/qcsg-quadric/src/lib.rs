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
