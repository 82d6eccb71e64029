//! Why a sampling run stopped without samples ([`SampleError`]): an invalid radius, or a limit
//! of [`crate::SampleLimits`] crossed.

/// Errors of [`sample`](crate::sample).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SampleError {
    /// The radius is not a positive finite number.
    InvalidRadius(f64),
    /// The run would emit more than [`SampleLimits::max_samples`](crate::SampleLimits::max_samples) samples (counting the
    /// rectangles the first pass holds for the second).
    TooManySamples {
        /// The limit.
        limit: u64,
        /// The quadric (index into [`Dnf::quadrics`](qcsg_csg::Dnf::quadrics)) being sampled when it was crossed.
        quadric: u32,
    },
    /// Eq. 22 set up for the literals sampled would take more memory than
    /// [`SampleLimits::max_samples`](crate::SampleLimits::max_samples) samples: each literal's
    /// distance holds the terms near it, and thousands of overlapping parts are near one another.
    DistancesTooLarge {
        /// The limit.
        limit: u64,
        /// The quadric (index into [`Dnf::quadrics`](qcsg_csg::Dnf::quadrics)) being sampled when it was crossed.
        quadric: u32,
    },
    /// The run would make more than [`SampleLimits::max_queries`](crate::SampleLimits::max_queries) distance queries.
    TooManyQueries {
        /// The limit.
        limit: u64,
        /// The quadric (index into [`Dnf::quadrics`](qcsg_csg::Dnf::quadrics)) being sampled when it was crossed.
        quadric: u32,
    },
}

impl std::fmt::Display for SampleError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::InvalidRadius(r) => {
                write!(f, "the sample radius must be positive and finite, got {r}")
            }
            Self::TooManySamples { limit, .. } => write!(
                f,
                "sampling at this radius needs more than {limit} samples (counting rectangles \
                 held for the second pass)"
            ),
            Self::DistancesTooLarge { limit, .. } => write!(
                f,
                "the distances set up for the surfaces sampled need more memory than {limit} \
                 samples (each surface's distance holds the terms near it)"
            ),
            Self::TooManyQueries { limit, .. } => write!(
                f,
                "sampling at this radius needs more than {limit} distance queries (surfaces \
                 that nearly coincide defeat the subdivision's proofs)"
            ),
        }
    }
}

impl std::error::Error for SampleError {}
