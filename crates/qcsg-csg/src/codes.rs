//! Stable diagnostic codes of the scene IR: errors E0600–E0699, warnings W0600–W0699.

/// The solid (or a term of its DNF) is unbounded.
pub const UNBOUNDED: &str = "E0600";
/// Expanding the scene to its DNF would exceed the term limit.
pub const TERM_LIMIT: &str = "E0601";
/// A transform is singular, so the part below it has no volume and was left out.
/// A warning: the rest of the solid is still built.
pub const SINGULAR_TRANSFORM: &str = "W0602";
/// There is no root to build a DNF from.
pub const NO_ROOT: &str = "E0603";
/// Sampling the surface at the requested radius would exceed the sample limit.
pub const SAMPLE_LIMIT: &str = "E0604";
/// Sampling the surface would exceed the limit on distance queries.
pub const QUERY_LIMIT: &str = "E0605";
/// Meshing a surface at the requested tolerance would exceed the triangle limit.
pub const TRIANGLE_LIMIT: &str = "E0606";

/// Every code with a one-line description, for the documentation table.
pub const ALL: &[(&str, &str)] = &[
    (UNBOUNDED, "the resulting solid is unbounded"),
    (TERM_LIMIT, "the DNF of the scene exceeds the term limit"),
    (
        SINGULAR_TRANSFORM,
        "a singular transform flattens a part to zero volume; it was left out",
    ),
    (NO_ROOT, "the scene has no root solid"),
    (
        SAMPLE_LIMIT,
        "sampling at the requested radius needs more samples than the limit",
    ),
    (
        QUERY_LIMIT,
        "sampling needs more distance queries than the limit (surfaces that nearly coincide)",
    ),
    (
        TRIANGLE_LIMIT,
        "meshing at the requested tolerance needs more triangles than the limit",
    ),
];
