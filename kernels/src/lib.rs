//! # tridist: fast, measured distance queries between triangles, segments and points
//!
//! Squared distances, closest points, intersection and within-margin tests for triangles,
//! segments and points, in `f32` and `f64`, on scalar, SSE4.1, AVX and AVX2+FMA kernels. Every
//! kernel variant is checked against an exact rational oracle (`tridist-oracle`); the measured
//! error of each variant on each input family is published in `reports/ACCURACY.md`.
//!
//! * Single queries on plain arrays: [`sqdist_triangle_triangle`],
//!   [`closest_points_triangle_triangle`], [`intersect_triangle_triangle`],
//!   [`within_margin_triangle_triangle`], [`sqdist_segment_segment`],
//!   [`sqdist_point_triangle`], ... (scalar kernel, no set-up).
//! * Batches: an [`Engine`] (one instruction-set variant, [`Isa`]) runs a query over pairs
//!   `a[i]` vs `b[i]` or one primitive against many ([`Prims`]), writing into caller-provided
//!   slices. Ask only for what the scene needs: squared distance only costs less than closest
//!   points; the within-margin query skips pairs whose boxes are already too far apart.
//!
//! ## Behaviour common to every query
//! * **Degenerate input**: a triangle whose vertices coincide or are collinear is treated as the
//!   point or segment it is; a zero-length segment as a point. Never NaN for finite input.
//! * **Touching / intersecting** triangles have squared distance exactly `0`.
//! * **Non-finite input** (any NaN or infinite coordinate): the squared distance and closest
//!   points are NaN, intersection answers `None`. Other lanes of a batch are unaffected.
//! * **Overflow**: when the squared distance exceeds the precision's range it is `+inf` (the
//!   distance itself may still be finite; take `sqrt` in a wider type if needed). Closest points
//!   stay finite. Intermediate overflow cannot happen: each query scales its input by a power of
//!   two first, exactly.
//! * **Underflow**: a squared distance below the smallest subnormal rounds to `0` (for f32 this
//!   happens for distances below about 2^-75).
//!
//! ## Precision
//! Error is measured as `E = |sqrt(D^) - d*| / (u*S)` (u the unit roundoff, S the largest
//! absolute coordinate), see `ACCURACY.md` at the repository root and the measured table in
//! `reports/ACCURACY.md`.
//!
//! ## Example
//! ```
//! let a = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
//! let b = [[0.0f32, 0.0, 2.0], [1.0, 0.0, 2.0], [0.0, 1.0, 2.0]];
//! assert_eq!(tridist::sqdist_triangle_triangle(&a, &b), 4.0);
//! assert_eq!(tridist::intersect_triangle_triangle(&a, &b), Some(false));
//! ```
//!
//! ## Soundness of the SIMD dispatch
//! The `#[target_feature]` kernels are reached only through an [`Engine`], whose variant was
//! confirmed by runtime detection, and the dispatcher checks detection again (one cached load)
//! before every batch. The batch plumbing is private to the crate; it cannot be named from
//! outside:
//! ```compile_fail,E0603
//! use tridist::driver::Job; // private module
//! ```
//! ```compile_fail,E0624
//! fn reach<T: tridist::Real>() {
//!     T::run_job(tridist::Isa::Avx2Fma, todo!()); // the seal's method is crate-private
//! }
//! ```
#![cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]

mod algo;
mod arch;
mod batch;
mod dispatch;
mod driver;
mod lanes;
mod real;

pub use batch::{Batch, PointBatch, SegmentBatch, TriangleBatch};
pub use dispatch::Isa;
pub use real::Real;

use driver::{DOut, Job, QueryKind, Src};

/// A point: `[x, y, z]`.
pub type Point<T> = [T; 3];
/// A segment: its two end points.
pub type Segment<T> = [Point<T>; 2];
/// A triangle: its three vertices.
pub type Triangle<T> = [Point<T>; 3];

/// A squared distance and the closest points realising it: `p` on the first primitive, `q` on
/// the second. For intersecting triangles `sqdist` is 0 and `p`, `q` are a point of contact
/// (equal up to rounding). Closest points are not unique for parallel features; any valid pair
/// may be returned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosestPoints<T> {
    /// Squared distance.
    pub sqdist: T,
    /// Closest point on the first primitive.
    pub p: Point<T>,
    /// Closest point on the second primitive.
    pub q: Point<T>,
}

/// Misuse of the batch API. Never a panic.
#[derive(Clone, Debug, PartialEq, Eq)]
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
    /// The variant is not supported by this CPU (or this target).
    Unavailable(Isa),
    /// A variant name that is not one of `scalar`, `sse41`, `avx`, `avx2fma`.
    UnknownIsa(String),
    /// The margin of a within-margin query is negative or not finite.
    InvalidMargin,
    /// Penalty-method options out of range (see [`PenaltyOptions`]).
    InvalidOptions,
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
            Error::Unavailable(i) => write!(f, "variant {i} is not available on this CPU"),
            Error::UnknownIsa(s) => {
                write!(f, "unknown variant {s:?} (expected scalar, sse41, avx or avx2fma)")
            }
            Error::InvalidMargin => write!(f, "margin must be finite and non-negative"),
            Error::InvalidOptions => write!(
                f,
                "penalty options: rho, reg and tol must be finite and positive, max_iter at least 1, start finite"
            ),
            Error::IndexOutOfRange { triangle, index, vertices } => {
                write!(f, "triangle {triangle} uses vertex index {index}, but there are {vertices} vertices")
            }
        }
    }
}

impl std::error::Error for Error {}

/// One side of a batch query: SoA columns (fastest for SIMD), a plain slice (AoS: the paper's
/// "non-SIMD layout"), or a single primitive broadcast against every primitive of the other side.
#[derive(Clone, Copy, Debug)]
pub enum Prims<'a, T, const K: usize> {
    /// SoA columns.
    Soa(&'a Batch<T, K>),
    /// Plain array of primitives.
    Aos(&'a [[Point<T>; K]]),
    /// One primitive against many.
    One(&'a [Point<T>; K]),
}

impl<'a, T, const K: usize> From<&'a Batch<T, K>> for Prims<'a, T, K> {
    fn from(b: &'a Batch<T, K>) -> Self {
        Prims::Soa(b)
    }
}
impl<'a, T, const K: usize> From<&'a [[Point<T>; K]]> for Prims<'a, T, K> {
    fn from(b: &'a [[Point<T>; K]]) -> Self {
        Prims::Aos(b)
    }
}
impl<'a, T, const K: usize> From<&'a Vec<[Point<T>; K]>> for Prims<'a, T, K> {
    fn from(b: &'a Vec<[Point<T>; K]>) -> Self {
        Prims::Aos(b)
    }
}
impl<'a, T, const K: usize> From<&'a [Point<T>; K]> for Prims<'a, T, K> {
    fn from(b: &'a [Point<T>; K]) -> Self {
        Prims::One(b)
    }
}

impl<'a, T: Real, const K: usize> Prims<'a, T, K> {
    fn len(&self) -> Option<usize> {
        match self {
            Prims::Soa(b) => Some(b.len()),
            Prims::Aos(s) => Some(s.len()),
            Prims::One(_) => None,
        }
    }
    fn src(&self) -> Src<'a, T> {
        match *self {
            Prims::Soa(b) => b.src(),
            Prims::Aos(s) => Src::Aos { flat: s.as_flattened().as_flattened(), len: s.len(), k: K },
            Prims::One(p) => Src::One { flat: p.as_flattened(), k: K },
        }
    }
}

/// Options of the penalty method ([`Engine::closest_points_triangle_triangle_penalty`]): the
/// speed-for-accuracy knob. `rho` and `reg` are relative to the pair's own curvature and `tol`
/// to its magnitude, so the same options behave the same at every scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PenaltyOptions<T> {
    /// Penalty weight (relative). Larger: points closer to their triangles, worse conditioning.
    pub rho: T,
    /// Regularisation added to the Hessian's diagonal (relative); the paper uses 1/rho^2.
    pub reg: T,
    /// Stop when the step, measured on the geometry, is below `tol * S`.
    pub tol: T,
    /// Iteration limit.
    pub max_iter: u32,
    /// Start point (a, b, g, d): barycentric parameters of both triangles.
    pub start: [T; 4],
}

impl<T: Real> Default for PenaltyOptions<T> {
    /// rho = 1/(4 sqrt(u)) (about 1e3 for f32, 2.4e7 for f64: larger rho makes the Newton
    /// system too ill-conditioned for the precision), reg = 1/rho^2 as in the paper,
    /// tol = 64 u, 32 iterations, start (1/3, 1/3, 1/3, 1/3).
    fn default() -> Self {
        let third = T::ONE / T::from_f64(3.0);
        let rho = 0.25 / T::UNIT_ROUNDOFF.to_f64().sqrt();
        PenaltyOptions {
            rho: T::from_f64(rho),
            reg: T::from_f64(1.0 / (rho * rho)),
            tol: T::UNIT_ROUNDOFF * T::from_f64(64.0),
            max_iter: 32,
            start: [third; 4],
        }
    }
}

impl<T: Real> PenaltyOptions<T> {
    fn is_valid(&self) -> bool {
        let pos = |x: T| x.is_finite() && x > T::ZERO;
        pos(self.rho)
            && pos(self.reg)
            && pos(self.tol)
            && self.max_iter >= 1
            && self.start.iter().all(|x| x.is_finite())
    }
}

/// Runs batch queries on one instruction-set variant.
///
/// Built only for a variant this CPU supports, so every method is safe to call.
///
/// # Example
/// ```
/// use tridist::{Engine, TriangleBatch};
/// let a = TriangleBatch::from_slice(&[[[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]; 10]);
/// let b = TriangleBatch::from_slice(&[[[0.0f32, 0.0, 3.0], [1.0, 0.0, 3.0], [0.0, 1.0, 3.0]]; 10]);
/// let mut out = vec![0.0f32; 10];
/// Engine::auto().sqdist_triangle_triangle(&a, &b, &mut out).unwrap();
/// assert!(out.iter().all(|&d| d == 9.0));
/// // lengths must agree: an error, not a panic
/// assert!(Engine::auto().sqdist_triangle_triangle(&a, &b, &mut out[..3]).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Engine {
    isa: Isa,
    threads: usize,
}

/// The environment variable that pins [`Engine::auto`] to one variant (`scalar`, `sse41`,
/// `avx`, `avx2fma`), for tests and benchmarks.
pub const ISA_ENV: &str = "TRIDIST_ISA";

impl Engine {
    /// An engine for `isa`, or [`Error::Unavailable`] when this CPU lacks it.
    pub fn new(isa: Isa) -> Result<Engine, Error> {
        if isa.is_available() {
            Ok(Engine { isa, threads: 1 })
        } else {
            Err(Error::Unavailable(isa))
        }
    }

    /// The scalar engine (always available).
    pub fn scalar() -> Engine {
        Engine { isa: Isa::Scalar, threads: 1 }
    }

    /// The best available variant, or the one named by `TRIDIST_ISA` when that is set.
    ///
    /// # Errors
    /// When `TRIDIST_ISA` names an unknown or unavailable variant.
    pub fn from_env() -> Result<Engine, Error> {
        match std::env::var(ISA_ENV) {
            Ok(s) if !s.is_empty() => {
                let isa = Isa::parse(&s).ok_or(Error::UnknownIsa(s))?;
                Engine::new(isa)
            }
            _ => Ok(Engine { isa: Isa::best(), threads: 1 }),
        }
    }

    /// [`Engine::from_env`], falling back to the best available variant when `TRIDIST_ISA` is
    /// unusable. Detection runs once and is cached.
    pub fn auto() -> Engine {
        Engine::from_env().unwrap_or(Engine { isa: Isa::best(), threads: 1 })
    }

    /// The variant this engine runs.
    pub fn isa(&self) -> Isa {
        self.isa
    }

    /// The same engine splitting each batch across `n` threads (std scoped threads, chunks of
    /// whole vectors; batches below 1024 pairs stay on the calling thread). `n = 0` means the
    /// number of available cores. Results are identical to the single-threaded ones.
    ///
    /// # Example
    /// ```
    /// use tridist::Engine;
    /// let a = vec![[[0.0f64, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]; 5000];
    /// let b = vec![[[0.0f64, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]]; 5000];
    /// let mut out = vec![0.0; 5000];
    /// Engine::auto().threads(2).sqdist_triangle_triangle(&a, &b, &mut out).unwrap();
    /// assert!(out.iter().all(|&d| d == 1.0));
    /// ```
    pub fn threads(self, n: usize) -> Engine {
        let n = if n == 0 { std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1) } else { n };
        Engine { threads: n.max(1), ..self }
    }

    #[allow(clippy::too_many_arguments)]
    fn exec<T: Real, const KA: usize, const KB: usize>(
        &self,
        query: QueryKind,
        a: Prims<'_, T, KA>,
        b: Prims<'_, T, KB>,
        param: T,
        d: DOut<'_, T>,
        p: Option<&mut [Point<T>]>,
        q: Option<&mut [Point<T>]>,
        penalty: Option<(PenaltyOptions<T>, &mut [u32])>,
    ) -> Result<(), Error> {
        let n = match (a.len(), b.len()) {
            (Some(x), Some(y)) if x != y => {
                return Err(Error::LengthMismatch { what: "b", expected: x, found: y })
            }
            (Some(x), _) | (None, Some(x)) => x,
            (None, None) => 1,
        };
        let dlen = match &d {
            DOut::Real(s) => s.len(),
            DOut::Flag(s) => s.len(),
        };
        let check = |what, len: usize| {
            if len == n {
                Ok(())
            } else {
                Err(Error::LengthMismatch { what, expected: n, found: len })
            }
        };
        check("out", dlen)?;
        if let Some(p) = &p {
            check("out_p", p.len())?;
        }
        if let Some(q) = &q {
            check("out_q", q.len())?;
        }
        let (options, mut iters) = match penalty {
            Some((o, it)) => {
                check("out_iters", it.len())?;
                if !o.is_valid() {
                    return Err(Error::InvalidOptions);
                }
                (o, Some(it))
            }
            None => (PenaltyOptions::default(), None),
        };
        let (sa, sb) = (a.src(), b.src());
        if self.threads <= 1 || n < 1024 {
            let mut job = Job { query, a: sa, b: sb, n, param, d, p, q, penalty: options, iters };
            <T as real::sealed::Sealed>::run_job(self.isa, &mut job);
            return Ok(());
        }
        // Chunks of whole 8-lane groups, one per thread; outputs split alike.
        let chunk = n.div_ceil(self.threads).div_ceil(8) * 8;
        let isa = self.isa;
        let mut d = d;
        let (mut p, mut q) = (p, q);
        std::thread::scope(|scope| {
            let mut start = 0;
            while start < n {
                let len = chunk.min(n - start);
                let (d_now, d_rest) = match d {
                    DOut::Real(s) => {
                        let (x, y) = s.split_at_mut(len);
                        (DOut::Real(x), DOut::Real(y))
                    }
                    DOut::Flag(s) => {
                        let (x, y) = s.split_at_mut(len);
                        (DOut::Flag(x), DOut::Flag(y))
                    }
                };
                d = d_rest;
                let (p_now, p_rest) = split_opt(p, len);
                let (q_now, q_rest) = split_opt(q, len);
                (p, q) = (p_rest, q_rest);
                let (it_now, it_rest) = split_opt(iters, len);
                iters = it_rest;
                let mut job = Job {
                    query,
                    a: sa.from(start),
                    b: sb.from(start),
                    n: len,
                    param,
                    d: d_now,
                    p: p_now,
                    q: q_now,
                    penalty: options,
                    iters: it_now,
                };
                scope.spawn(move || <T as real::sealed::Sealed>::run_job(isa, &mut job));
                start += len;
            }
        });
        Ok(())
    }

    /// Squared triangle-triangle distances (PQP TriDist, made robust; see
    /// [`sqdist_triangle_triangle`] for behaviour), `out[i]` for pair `i`.
    ///
    /// # Errors
    /// [`Error::LengthMismatch`] when `a`, `b` and `out` disagree in length (a [`Prims::One`]
    /// side matches any length). An empty batch is fine and writes nothing.
    ///
    /// # Precision
    /// Excess error E per input family, variant and precision: `reports/ACCURACY.md`
    /// (query `tri_tri`), enforced by the bound table in `scenes/src/bounds.rs`.
    ///
    /// # Performance
    /// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
    pub fn sqdist_triangle_triangle<'a, T: Real>(
        &self,
        a: impl Into<Prims<'a, T, 3>>,
        b: impl Into<Prims<'a, T, 3>>,
        out: &mut [T],
    ) -> Result<(), Error> {
        self.exec(QueryKind::TriTri, a.into(), b.into(), T::ZERO, DOut::Real(out), None, None, None)
    }

    /// Squared distances and closest points (`out_p` on `a`, `out_q` on `b`).
    ///
    /// # Errors
    /// As [`Engine::sqdist_triangle_triangle`], also for `out_p`/`out_q`.
    ///
    /// # Precision
    /// Excess error E per input family, variant and precision: `reports/ACCURACY.md`
    /// (query `tri_tri`), enforced by the bound table in `scenes/src/bounds.rs`.
    ///
    /// # Performance
    /// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
    pub fn closest_points_triangle_triangle<'a, T: Real>(
        &self,
        a: impl Into<Prims<'a, T, 3>>,
        b: impl Into<Prims<'a, T, 3>>,
        out: &mut [T],
        out_p: &mut [Point<T>],
        out_q: &mut [Point<T>],
    ) -> Result<(), Error> {
        let (a, b) = (a.into(), b.into());
        self.exec(QueryKind::TriTri, a, b, T::ZERO, DOut::Real(out), Some(out_p), Some(out_q), None)
    }

    /// Squared distances by brute force: the minimum over the 15 feature pairs (9 edge-edge,
    /// 6 vertex-face) unless the separating-axis test finds an overlap (then 0).
    ///
    /// # Errors
    /// As [`Engine::sqdist_triangle_triangle`].
    ///
    /// # Precision
    /// Excess error E per input family, variant and precision: `reports/ACCURACY.md`
    /// (query `tri_tri_brute`), enforced by the bound table in `scenes/src/bounds.rs`.
    ///
    /// # Performance
    /// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
    pub fn sqdist_triangle_triangle_brute<'a, T: Real>(
        &self,
        a: impl Into<Prims<'a, T, 3>>,
        b: impl Into<Prims<'a, T, 3>>,
        out: &mut [T],
    ) -> Result<(), Error> {
        self.exec(QueryKind::TriTriBrute, a.into(), b.into(), T::ZERO, DOut::Real(out), None, None, None)
    }

    /// Brute force with closest points.
    ///
    /// # Errors
    /// As [`Engine::closest_points_triangle_triangle`].
    ///
    /// # Precision
    /// Excess error E per input family, variant and precision: `reports/ACCURACY.md`
    /// (query `tri_tri_brute`), enforced by the bound table in `scenes/src/bounds.rs`.
    ///
    /// # Performance
    /// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
    pub fn closest_points_triangle_triangle_brute<'a, T: Real>(
        &self,
        a: impl Into<Prims<'a, T, 3>>,
        b: impl Into<Prims<'a, T, 3>>,
        out: &mut [T],
        out_p: &mut [Point<T>],
        out_q: &mut [Point<T>],
    ) -> Result<(), Error> {
        let (a, b) = (a.into(), b.into());
        self.exec(QueryKind::TriTriBrute, a, b, T::ZERO, DOut::Real(out), Some(out_p), Some(out_q), None)
    }

    /// Intersection only (separating axes): `Some(true)` when the triangles touch or overlap,
    /// `Some(false)` when disjoint, `None` for non-finite input.
    ///
    /// # Errors
    /// As [`Engine::sqdist_triangle_triangle`].
    ///
    /// # Precision
    /// Excess error E per input family, variant and precision: `reports/ACCURACY.md`
    /// (query `intersect`), enforced by the bound table in `scenes/src/bounds.rs`.
    ///
    /// # Performance
    /// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
    pub fn intersect_triangle_triangle<'a, T: Real>(
        &self,
        a: impl Into<Prims<'a, T, 3>>,
        b: impl Into<Prims<'a, T, 3>>,
        out: &mut [Option<bool>],
    ) -> Result<(), Error> {
        self.exec(QueryKind::Intersect, a.into(), b.into(), T::ZERO, DOut::Flag(out), None, None, None)
    }

    /// Within-margin: `out[i]` is the squared distance when the distance is at most `margin`,
    /// else `+inf`. Pairs whose bounding boxes are farther apart than `margin` skip the distance
    /// computation (a batch of SIMD lanes skips it when all its lanes are far).
    ///
    /// # Errors
    /// [`Error::InvalidMargin`] for a negative or non-finite margin; lengths as
    /// [`Engine::sqdist_triangle_triangle`].
    ///
    /// # Precision
    /// Excess error E per input family, variant and precision: `reports/ACCURACY.md`
    /// (query `tri_tri`), enforced by the bound table in `scenes/src/bounds.rs`.
    ///
    /// # Performance
    /// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
    pub fn within_margin_triangle_triangle<'a, T: Real>(
        &self,
        a: impl Into<Prims<'a, T, 3>>,
        b: impl Into<Prims<'a, T, 3>>,
        margin: T,
        out: &mut [T],
    ) -> Result<(), Error> {
        if !(margin.is_finite() && margin >= T::ZERO) {
            return Err(Error::InvalidMargin);
        }
        self.exec(QueryKind::Within, a.into(), b.into(), margin, DOut::Real(out), None, None, None)
    }

    /// Triangle-triangle distance by Krestenitis & Koziara's penalty method (seed 003): a
    /// regularised Newton iteration on the barycentric parameters of both triangles, each lane
    /// iterating independently. Writes the squared distance of the returned points, the points
    /// (`out_p` near `a`, `out_q` near `b`) and the iterations used.
    ///
    /// # Behaviour
    /// An approximation whose accuracy the caller trades for speed with
    /// [`PenaltyOptions`]: the points may lie outside their triangles by about 1/rho (in
    /// barycentric units), so the distance can be *below* the true one; intersecting pairs give
    /// a small positive or zero distance; parallel faces have many minimisers (the
    /// regularisation picks one); degenerate triangles are handled by the regularisation. NaN
    /// input gives NaN. Measured errors per family: `reports/ACCURACY.md` (query `penalty`).
    ///
    /// # Errors
    /// As [`Engine::closest_points_triangle_triangle`], also for `out_iters`.
    ///
    /// # Precision
    /// Excess error E per input family, variant and precision: `reports/ACCURACY.md`
    /// (query `penalty`), enforced by the bound table in `scenes/src/bounds.rs`.
    ///
    /// # Performance
    /// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
    #[allow(clippy::too_many_arguments)]
    pub fn closest_points_triangle_triangle_penalty<'a, T: Real>(
        &self,
        a: impl Into<Prims<'a, T, 3>>,
        b: impl Into<Prims<'a, T, 3>>,
        options: &PenaltyOptions<T>,
        out: &mut [T],
        out_p: &mut [Point<T>],
        out_q: &mut [Point<T>],
        out_iters: &mut [u32],
    ) -> Result<(), Error> {
        let (a, b) = (a.into(), b.into());
        let (d, p, q) = (DOut::Real(out), Some(out_p), Some(out_q));
        self.exec(QueryKind::Penalty, a, b, T::ZERO, d, p, q, Some((*options, out_iters)))
    }

    /// Squared segment-segment distances (Ericson 5.1.9 with a relative parallel test).
    ///
    /// # Errors
    /// As [`Engine::sqdist_triangle_triangle`].
    ///
    /// # Precision
    /// Excess error E per input family, variant and precision: `reports/ACCURACY.md`
    /// (query `seg_seg`), enforced by the bound table in `scenes/src/bounds.rs`.
    ///
    /// # Performance
    /// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
    pub fn sqdist_segment_segment<'a, T: Real>(
        &self,
        a: impl Into<Prims<'a, T, 2>>,
        b: impl Into<Prims<'a, T, 2>>,
        out: &mut [T],
    ) -> Result<(), Error> {
        self.exec(QueryKind::SegSeg, a.into(), b.into(), T::ZERO, DOut::Real(out), None, None, None)
    }

    /// Squared segment-segment distances and closest points.
    ///
    /// # Errors
    /// As [`Engine::closest_points_triangle_triangle`].
    ///
    /// # Precision
    /// Excess error E per input family, variant and precision: `reports/ACCURACY.md`
    /// (query `seg_seg`), enforced by the bound table in `scenes/src/bounds.rs`.
    ///
    /// # Performance
    /// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
    pub fn closest_points_segment_segment<'a, T: Real>(
        &self,
        a: impl Into<Prims<'a, T, 2>>,
        b: impl Into<Prims<'a, T, 2>>,
        out: &mut [T],
        out_p: &mut [Point<T>],
        out_q: &mut [Point<T>],
    ) -> Result<(), Error> {
        let (a, b) = (a.into(), b.into());
        self.exec(QueryKind::SegSeg, a, b, T::ZERO, DOut::Real(out), Some(out_p), Some(out_q), None)
    }

    /// Squared point-triangle distances (Ericson 5.1.5). `a` holds points (`[Point; 1]`).
    ///
    /// # Errors
    /// As [`Engine::sqdist_triangle_triangle`].
    ///
    /// # Precision
    /// Excess error E per input family, variant and precision: `reports/ACCURACY.md`
    /// (query `point_tri`), enforced by the bound table in `scenes/src/bounds.rs`.
    ///
    /// # Performance
    /// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
    pub fn sqdist_point_triangle<'a, T: Real>(
        &self,
        a: impl Into<Prims<'a, T, 1>>,
        b: impl Into<Prims<'a, T, 3>>,
        out: &mut [T],
    ) -> Result<(), Error> {
        self.exec(QueryKind::PointTri, a.into(), b.into(), T::ZERO, DOut::Real(out), None, None, None)
    }

    /// Squared point-triangle distances and the closest points on the triangles (`out_q`).
    ///
    /// # Errors
    /// As [`Engine::closest_points_triangle_triangle`].
    ///
    /// # Precision
    /// Excess error E per input family, variant and precision: `reports/ACCURACY.md`
    /// (query `point_tri`), enforced by the bound table in `scenes/src/bounds.rs`.
    ///
    /// # Performance
    /// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
    pub fn closest_point_point_triangle<'a, T: Real>(
        &self,
        a: impl Into<Prims<'a, T, 1>>,
        b: impl Into<Prims<'a, T, 3>>,
        out: &mut [T],
        out_q: &mut [Point<T>],
    ) -> Result<(), Error> {
        self.exec(QueryKind::PointTri, a.into(), b.into(), T::ZERO, DOut::Real(out), None, Some(out_q), None)
    }
}

fn split_opt<T>(s: Option<&mut [T]>, at: usize) -> (Option<&mut [T]>, Option<&mut [T]>) {
    match s {
        Some(s) => {
            let (x, y) = s.split_at_mut(at);
            (Some(x), Some(y))
        }
        None => (None, None),
    }
}

fn single<T: Real, const KA: usize, const KB: usize>(
    query: QueryKind,
    a: &[Point<T>; KA],
    b: &[Point<T>; KB],
    param: T,
) -> ClosestPoints<T> {
    let mut d = [T::ZERO];
    let mut p = [[T::ZERO; 3]];
    let mut q = [[T::ZERO; 3]];
    let r = Engine::scalar().exec(
        query,
        Prims::One(a),
        Prims::One(b),
        param,
        DOut::Real(&mut d),
        Some(&mut p),
        Some(&mut q),
        None,
    );
    debug_assert!(r.is_ok());
    ClosestPoints { sqdist: d[0], p: p[0], q: q[0] }
}

/// Squared distance between two triangles.
///
/// # Behaviour
/// PQP's TriDist (Larsen et al., seed 000 listing 13) with certified early exits: the nine edge
/// pairs are tried first, an edge pair is accepted only if the plane through its closest points
/// separates all six vertices; then the vertex-face case; pairs neither case decides get the
/// brute-force answer. Intersecting or touching triangles give `0`; degenerate triangles are
/// treated as the segments or points they are; NaN/inf input gives NaN; an overflowing result
/// gives `+inf`.
///
/// # Precision
/// Measured per input family in `reports/ACCURACY.md`; bounds enforced by the test suite.
///
/// # Performance
/// The scalar kernel; for many pairs use [`Engine::sqdist_triangle_triangle`] on SoA batches.
///
/// # Example
/// ```
/// let a = [[0.0f64, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// let b = [[2.0f64, 0.0, 0.0], [3.0, 0.0, 0.0], [2.0, 1.0, 0.0]]; // coplanar, 1 apart
/// assert_eq!(tridist::sqdist_triangle_triangle(&a, &b), 1.0);
/// ```
pub fn sqdist_triangle_triangle<T: Real>(a: &Triangle<T>, b: &Triangle<T>) -> T {
    single(QueryKind::TriTri, a, b, T::ZERO).sqdist
}

/// Squared distance and closest points of two triangles (see [`sqdist_triangle_triangle`]).
///
/// # Example
/// ```
/// let a = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// let b = [[0.25f32, 0.25, 1.0], [0.25, 0.25, 5.0], [3.0, 3.0, 5.0]];
/// let c = tridist::closest_points_triangle_triangle(&a, &b);
/// assert_eq!(c.sqdist, 1.0);
/// assert_eq!(c.q, [0.25, 0.25, 1.0]);
/// ```
///
/// # Precision
/// Excess error E per input family, variant and precision: `reports/ACCURACY.md`
/// (query `tri_tri`), enforced by the bound table in `scenes/src/bounds.rs`.
///
/// # Performance
/// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
pub fn closest_points_triangle_triangle<T: Real>(a: &Triangle<T>, b: &Triangle<T>) -> ClosestPoints<T> {
    single(QueryKind::TriTri, a, b, T::ZERO)
}

/// Squared triangle distance by brute force (15 feature pairs + separating-axis overlap test),
/// the baseline of Krestenitis & Koziara. Same behaviour as [`sqdist_triangle_triangle`].
///
/// # Example
/// ```
/// let a = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// let b = [[0.2f32, 0.2, -1.0], [0.2, 0.2, 1.0], [5.0, 5.0, 0.0]]; // pierces a
/// assert_eq!(tridist::sqdist_triangle_triangle_brute(&a, &b), 0.0);
/// ```
///
/// # Precision
/// Excess error E per input family, variant and precision: `reports/ACCURACY.md`
/// (query `tri_tri_brute`), enforced by the bound table in `scenes/src/bounds.rs`.
///
/// # Performance
/// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
pub fn sqdist_triangle_triangle_brute<T: Real>(a: &Triangle<T>, b: &Triangle<T>) -> T {
    single(QueryKind::TriTriBrute, a, b, T::ZERO).sqdist
}

/// Brute-force squared distance with closest points.
///
/// # Precision
/// Excess error E per input family, variant and precision: `reports/ACCURACY.md`
/// (query `tri_tri_brute`), enforced by the bound table in `scenes/src/bounds.rs`.
///
/// # Performance
/// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
pub fn closest_points_triangle_triangle_brute<T: Real>(a: &Triangle<T>, b: &Triangle<T>) -> ClosestPoints<T> {
    single(QueryKind::TriTriBrute, a, b, T::ZERO)
}

/// Do two triangles touch or overlap? Separating-axis test after PQP's TriContact (seed 000
/// listings 11-12): 17 axes, early out.
///
/// # Behaviour
/// `Some(true)` for touching or intersecting triangles, `Some(false)` for disjoint ones, `None`
/// when a coordinate is NaN or infinite. Two degenerate triangles (segments/points) are decided
/// by their edge distance.
///
/// # Example
/// ```
/// let a = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// let b = [[1.0f32, 0.0, 0.0], [2.0, 0.0, 0.0], [1.0, 1.0, 0.0]]; // shares a vertex
/// assert_eq!(tridist::intersect_triangle_triangle(&a, &b), Some(true));
/// let c = [[0.0f32, 0.0, f32::NAN], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// assert_eq!(tridist::intersect_triangle_triangle(&a, &c), None);
/// ```
///
/// # Precision
/// Excess error E per input family, variant and precision: `reports/ACCURACY.md`
/// (query `intersect`), enforced by the bound table in `scenes/src/bounds.rs`.
///
/// # Performance
/// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
pub fn intersect_triangle_triangle<T: Real>(a: &Triangle<T>, b: &Triangle<T>) -> Option<bool> {
    let mut out = [None];
    let r = Engine::scalar().intersect_triangle_triangle(Prims::One(a), Prims::One(b), &mut out);
    debug_assert!(r.is_ok());
    out[0]
}

/// Is the distance at most `margin`, and if so, what is its square?
///
/// # Behaviour
/// `Ok(Some(d2))` when the distance is at most `margin` (d2 as [`sqdist_triangle_triangle`]),
/// `Ok(None)` when farther. Pairs whose bounding boxes are farther apart than `margin` are
/// rejected without the distance computation. Non-finite triangle input gives `Ok(Some(NaN))`.
///
/// # Errors
/// [`Error::InvalidMargin`] when `margin` is negative or not finite.
///
/// # Example
/// ```
/// let a = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// let b = [[0.0f32, 0.0, 2.0], [1.0, 0.0, 2.0], [0.0, 1.0, 2.0]];
/// assert_eq!(tridist::within_margin_triangle_triangle(&a, &b, 3.0), Ok(Some(4.0)));
/// assert_eq!(tridist::within_margin_triangle_triangle(&a, &b, 1.0), Ok(None));
/// ```
///
/// # Precision
/// Excess error E per input family, variant and precision: `reports/ACCURACY.md`
/// (query `tri_tri`), enforced by the bound table in `scenes/src/bounds.rs`.
///
/// # Performance
/// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
pub fn within_margin_triangle_triangle<T: Real>(
    a: &Triangle<T>,
    b: &Triangle<T>,
    margin: T,
) -> Result<Option<T>, Error> {
    let mut out = [T::ZERO];
    Engine::scalar().within_margin_triangle_triangle(Prims::One(a), Prims::One(b), margin, &mut out)?;
    Ok(if out[0] == T::INFINITY { None } else { Some(out[0]) })
}

/// Squared distance between two segments (Ericson, Real-Time Collision Detection 5.1.9; seed
/// 000 listing 9), with a relative parallel test and zero-length segments treated as points.
///
/// # Example
/// ```
/// let a = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0]];
/// let b = [[0.5f32, 1.0, -1.0], [0.5, 1.0, 1.0]];
/// assert_eq!(tridist::sqdist_segment_segment(&a, &b), 1.0);
/// ```
///
/// # Precision
/// Excess error E per input family, variant and precision: `reports/ACCURACY.md`
/// (query `seg_seg`), enforced by the bound table in `scenes/src/bounds.rs`.
///
/// # Performance
/// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
pub fn sqdist_segment_segment<T: Real>(a: &Segment<T>, b: &Segment<T>) -> T {
    single(QueryKind::SegSeg, a, b, T::ZERO).sqdist
}

/// Squared distance and closest points of two segments.
///
/// # Precision
/// Excess error E per input family, variant and precision: `reports/ACCURACY.md`
/// (query `seg_seg`), enforced by the bound table in `scenes/src/bounds.rs`.
///
/// # Performance
/// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
pub fn closest_points_segment_segment<T: Real>(a: &Segment<T>, b: &Segment<T>) -> ClosestPoints<T> {
    single(QueryKind::SegSeg, a, b, T::ZERO)
}

/// Squared distance from a point to a triangle (Ericson 5.1.5; seed 000 listing 10).
/// Degenerate triangles are treated as their segments or point.
///
/// # Example
/// ```
/// let t = [[0.0f64, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// assert_eq!(tridist::sqdist_point_triangle(&[0.25, 0.25, 2.0], &t), 4.0);
/// ```
///
/// # Precision
/// Excess error E per input family, variant and precision: `reports/ACCURACY.md`
/// (query `point_tri`), enforced by the bound table in `scenes/src/bounds.rs`.
///
/// # Performance
/// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
pub fn sqdist_point_triangle<T: Real>(p: &Point<T>, t: &Triangle<T>) -> T {
    single(QueryKind::PointTri, &[*p], t, T::ZERO).sqdist
}

/// Squared distance from a point to a triangle and the closest point on it (`q`; `p` is the
/// query point).
///
/// # Precision
/// Excess error E per input family, variant and precision: `reports/ACCURACY.md`
/// (query `point_tri`), enforced by the bound table in `scenes/src/bounds.rs`.
///
/// # Performance
/// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
pub fn closest_point_point_triangle<T: Real>(p: &Point<T>, t: &Triangle<T>) -> ClosestPoints<T> {
    single(QueryKind::PointTri, &[*p], t, T::ZERO)
}
