//! Misuse of the API: every batch and single query reports it as an [`Error`], never a panic.

use crate::{Isa, Query};

/// Misuse of the batch API (or of a single query's options). Never a panic.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Error {
    /// Two inputs (or an input and an output) that must have the same length do not.
    LengthMismatch {
        /// Which argument.
        what: &'static str,
        /// The length it must have.
        expected: usize,
        /// The length it has.
        found: usize,
    },
    /// The primitives passed do not have the points the query takes (for example segments
    /// given to a triangle query through [`crate::Engine::run`]).
    Arity {
        /// The query.
        query: Query,
        /// Points per primitive it takes on each side.
        expected: (usize, usize),
        /// Points per primitive given.
        found: (usize, usize),
    },
    /// The variant is not supported by this CPU (or this target), or not compiled in
    /// ([`Isa::is_compiled`]).
    Unavailable(Isa),
    /// A variant name that is not one of `scalar`, `sse41`, `avx`, `avx2fma`, `avx512vl`,
    /// `avx512`.
    UnknownIsa(String),
    /// An output the query does not compute was asked for: distances, closest points or
    /// intervals of [`Query::Intersect`], whose separating-axis test decides a verdict without
    /// computing a distance (ask for [`crate::Outputs::verdicts`], or run [`Query::TriTri`]).
    NoSuchOutput {
        /// The query.
        query: Query,
        /// The output asked for (`sqdist`, `closest_points`, `p`, `q`, `intervals`).
        output: &'static str,
    },
    /// The margin of a within-margin query is negative or not finite.
    InvalidMargin,
    /// Penalty-method options out of range (see [`crate::PenaltyOptions`]).
    InvalidOptions,
    /// A tolerance that is negative or NaN (see [`crate::Tolerance`]).
    InvalidTolerance,
    /// A pose that is not finite (see [`crate::Pose`]).
    InvalidPose,
    /// A rotation axis that is zero or not finite, or an angle that is not finite
    /// ([`crate::Pose::from_axis_angle`]).
    InvalidRotation,
    /// A tree width outside `2..=8` ([`crate::Mesh::with_width`]).
    InvalidTreeWidth(usize),
    /// A leaf size outside `1..=8` ([`crate::Mesh::with_shape`]).
    InvalidLeafSize(usize),
    /// A mesh vertex has a NaN or infinite coordinate ([`crate::Mesh::new`]).
    NonFiniteVertex {
        /// The vertex number.
        vertex: usize,
    },
    /// A coordinate is NaN or infinite: a query point that is not finite, or a mesh whose
    /// moved bounding box leaves the precision's range (a moved vertex could overflow).
    NonFiniteCoordinate,
    /// A setting the query does not offer: [`crate::Tolerance::CORRECTLY_ROUNDED`] for the
    /// penalty method (an approximation) and the closest point of a mesh.
    Unsupported {
        /// The query (`penalty`, `mesh_distance`, ...).
        query: &'static str,
        /// The setting.
        setting: &'static str,
    },
    /// Under [`crate::Tolerance::CORRECTLY_ROUNDED`], a mesh query whose correctly rounded
    /// answer needs a pair that neither its certified interval nor a proof decided: build with
    /// the `exact` feature (the oracle decides every pair), or use another tolerance.
    Undecided,
    /// A mesh index names no vertex.
    IndexOutOfRange {
        /// Triangle number.
        triangle: usize,
        /// The index.
        index: usize,
        /// How many vertices there are.
        vertices: usize,
    },
}

impl core::fmt::Display for Error {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::LengthMismatch { what, expected, found } => {
                write!(f, "length mismatch: {what} has {found} elements, expected {expected}")
            }
            Error::Arity { query, expected, found } => write!(
                f,
                "query {query} takes primitives of {} and {} points, got {} and {}",
                expected.0, expected.1, found.0, found.1
            ),
            Error::Unavailable(i) if !i.is_compiled() => {
                write!(f, "variant {i} is not compiled in (enable the `{i}` feature of tridist)")
            }
            Error::Unavailable(i) => write!(f, "variant {i} is not available on this CPU"),
            Error::UnknownIsa(s) => {
                write!(f, "unknown variant {s:?} (expected scalar, sse41, avx, avx2fma, avx512vl or avx512)")
            }
            Error::NoSuchOutput { query, output } => write!(
                f,
                "query {query} computes no {output}: it decides intersection only (ask for verdicts, or run tri_tri for distances)"
            ),
            Error::InvalidMargin => write!(f, "margin must be finite and non-negative"),
            Error::InvalidOptions => write!(
                f,
                "penalty options: rho, reg and tol must be finite and positive, max_iter at least 1, start finite"
            ),
            Error::InvalidTolerance => write!(f, "tolerances must be non-negative (inf allowed), not NaN"),
            Error::InvalidPose => write!(f, "pose rotation and translation must be finite"),
            Error::InvalidRotation => {
                write!(f, "a rotation needs a finite, non-zero axis and a finite angle")
            }
            Error::InvalidTreeWidth(w) => write!(f, "tree width {w}: a node has 2 to 8 children"),
            Error::InvalidLeafSize(n) => write!(f, "leaf size {n}: a leaf holds 1 to 8 triangles"),
            Error::NonFiniteVertex { vertex } => write!(f, "vertex {vertex} has a NaN or infinite coordinate"),
            Error::NonFiniteCoordinate => {
                write!(f, "a coordinate is NaN or infinite (a query point, or a vertex moved out of range)")
            }
            Error::Unsupported { query, setting } => write!(f, "{query} does not offer {setting}"),
            Error::Undecided => write!(
                f,
                "the correctly rounded answer needs the exact oracle (build with the `exact` feature)"
            ),
            Error::IndexOutOfRange { triangle, index, vertices } => {
                write!(f, "triangle {triangle} uses vertex index {index}, but there are {vertices} vertices")
            }
        }
    }
}

impl std::error::Error for Error {}
