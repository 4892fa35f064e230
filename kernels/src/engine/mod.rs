//! The engine: runs batch queries on one instruction-set variant, with a tolerance, optional
//! threads, and the outputs the caller asks for.

mod options;
mod rounded;
#[cfg(test)]
mod tests;
mod threads;

pub use options::{Outputs, PenaltyOptions, Prims, Tolerance};
pub(crate) use threads::par_map_init;

use crate::algo::Params;
use crate::drv::Job;
use crate::ClosestPoints;
use crate::Error;
use crate::Intersection;
use crate::Isa;
use crate::PathCounts;
use crate::Query;
use crate::Real;
use std::sync::OnceLock;
use threads::run_pieces;

/// Runs batch queries on one instruction-set variant.
///
/// Built only for a variant this CPU supports (and every batch checks detection again), so
/// every method is safe to call.
///
/// # Example
/// ```
/// use tridist::{Engine, TriangleBatch};
/// let a = TriangleBatch::from_slice(&[[[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]; 10]);
/// let b = TriangleBatch::from_slice(&[[[0.0f32, 0.0, 3.0], [1.0, 0.0, 3.0], [0.0, 1.0, 3.0]]; 10]);
/// let mut out = vec![0.0f32; 10];
/// let counts = Engine::auto().sqdist_triangle_triangle(&a, &b, &mut out).unwrap();
/// assert!(out.iter().all(|&d| d == 9.0));
/// assert_eq!(counts.pairs, 10);
/// // lengths must agree: an error, not a panic
/// assert!(Engine::auto().sqdist_triangle_triangle(&a, &b, &mut out[..3]).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Engine {
    isa: Isa,
    threads: usize,
    tol: Tolerance,
    exact: bool,
    margin: f64,
    /// `None`: the defaults of the batch's precision.
    penalty: Option<PenaltyOptions<f64>>,
    /// Triangle-triangle distance starts with its quick stage ([`Engine::quick_stage`]).
    quick: bool,
}

/// The environment variable that pins [`Engine::auto`] to one variant (`scalar`, `sse41`,
/// `avx`, `avx2fma`, `avx512vl`, `avx512`), for tests and benchmarks. Read once per process.
pub const ISA_ENV: &str = "TRIDIST_ISA";

// (checked when the crate compiles: pieces are whole chunks of the driver)
const _: () = assert!(Engine::PIECE.is_multiple_of(crate::drv::CHUNK));

/// Building an engine: every setter takes the engine by value and returns the changed one, and
/// none fails (as [`std::thread::Builder`]'s). A setting is checked where it is used: every
/// query on an engine with an invalid setting returns that setting's error
/// ([`Error::InvalidTolerance`], [`Error::InvalidMargin`], [`Error::InvalidOptions`]) before it
/// reads its input, and [`Engine::check`] returns the same error up front. Only the
/// constructors that depend on the machine ([`Engine::new`], [`Engine::from_env`]) return a
/// `Result`.
impl Engine {
    /// Pieces of a batch split over threads ([`Engine::threads`]) are multiples of this many
    /// pairs (a multiple of the SoA padding and of the driver's chunk): each piece costs a lock,
    /// an entry point's set-up and its own open-pair lists, so on small batches fewer pieces
    /// win (`docs/notes/kernel-speed.md` in the repository has the measurements). May change
    /// in a minor version.
    pub const PIECE: usize = 512;

    /// Batches below this many pairs stay on the calling thread whatever [`Engine::threads`]
    /// says. May change in a minor version.
    pub const MIN_PARALLEL: usize = 2048;

    /// How long the calling thread of a split batch waits awake for the helpers' last pieces
    /// before it sleeps (with the default `rayon` feature; without it the helpers are scoped
    /// threads and it joins them at once). The helpers' last pieces (a sixteenth of a thread's
    /// share each) end within it on batches of up to a few milliseconds, where a wake-up costs
    /// most; a longer batch loses one wake-up against far more work; and a helper descheduled
    /// by the system costs the caller no more than this much of its core.
    pub const WAIT_AWAKE: std::time::Duration = threads::WAIT_AWAKE;

    fn with_isa(isa: Isa) -> Engine {
        Engine {
            isa,
            threads: 1,
            tol: Tolerance::DEFAULT,
            exact: cfg!(feature = "exact"),
            margin: 0.0,
            penalty: None,
            quick: true,
        }
    }

    /// An engine for `isa`, or [`Error::Unavailable`] when this CPU lacks it.
    pub fn new(isa: Isa) -> Result<Engine, Error> {
        if isa.is_available() {
            Ok(Engine::with_isa(isa))
        } else {
            Err(Error::Unavailable(isa))
        }
    }

    /// The scalar engine (always available).
    pub fn scalar() -> Engine {
        Engine::with_isa(Isa::Scalar)
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
            _ => Ok(Engine::with_isa(Isa::best())),
        }
    }

    /// [`Engine::from_env`], falling back to the best available variant when `TRIDIST_ISA` is
    /// unusable. The environment is read and the CPU detected once per process.
    pub fn auto() -> Engine {
        static AUTO: OnceLock<Engine> = OnceLock::new();
        *AUTO.get_or_init(|| Engine::from_env().unwrap_or(Engine::with_isa(Isa::best())))
    }

    /// The variant this engine runs.
    pub fn isa(&self) -> Isa {
        self.isa
    }

    /// The engine a mesh query runs its leaf batches and node tests on: this one, except that
    /// [`Isa::Avx512`] runs [`Isa::Avx512Vl`] (bit for bit the same answers). A traversal's
    /// leaf batches hold a few pairs each, and 16-lane vectors were 3-5 % slower there
    /// (`TRIDIST_ISA=avx2fma|avx512 spin mesh distance|contacts|intersect 2|5|9 f32 1 1`,
    /// Armadillo against fandisk: distance at pose 9 0.376 against 0.386 ms, contacts at
    /// pose 5 13.2 against 14.0 ms); the 8 lanes of [`Isa::Avx2Fma`] with AVX-512VL's 32
    /// registers were faster again (docs/notes/kernel-speed.md, "The same 8 lanes with 32 registers").
    pub(crate) fn for_small_batches(&self) -> Engine {
        match self.isa {
            Isa::Avx512 if Isa::Avx512Vl.is_available() => Engine { isa: Isa::Avx512Vl, ..*self },
            Isa::Avx512 if Isa::Avx2Fma.is_available() => Engine { isa: Isa::Avx2Fma, ..*self },
            _ => *self,
        }
    }

    /// The number of threads a large batch is split over ([`Engine::threads`]; 1 by default).
    pub fn thread_count(&self) -> usize {
        self.threads
    }

    /// The same engine splitting each batch over `n` threads (`0`: every available core), in
    /// pieces that idle threads take from busy ones: the calling thread and `n - 1` helpers (a
    /// persistent rayon pool with the default `rayon` feature, std scoped threads without it).
    /// The caller takes pieces from the front of the batch and the helpers from the back, and
    /// waits for the helpers' last pieces awake (spinning briefly, then yielding its core, at
    /// most [`Engine::WAIT_AWAKE`]) before it sleeps: a batch that takes tens of microseconds is not
    /// lost to waking threads. Pieces are multiples of [`Engine::PIECE`] pairs; batches below
    /// [`Engine::MIN_PARALLEL`] pairs stay on the calling thread. Results are identical to the
    /// single-threaded ones. A system that refuses to start the helpers (out of threads) gets
    /// the batch answered on the threads it has, the calling thread at worst: no panic, the
    /// same answers.
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
        Engine { threads: n, ..self }
    }

    /// The same engine with another tolerance ([`Tolerance`]). A tolerance with a negative or
    /// NaN entry makes every query return [`Error::InvalidTolerance`] ([`Engine::check`]).
    pub fn tolerance(self, tol: Tolerance) -> Engine {
        Engine { tol, ..self }
    }

    /// The tolerance in use.
    pub fn current_tolerance(&self) -> Tolerance {
        self.tol
    }

    /// The same engine with (`true`, the default when the crate is built with the `exact`
    /// feature) or without the exact oracle as the last escalation step. Without the feature
    /// this is always off.
    pub fn exact(self, on: bool) -> Engine {
        Engine { exact: on && cfg!(feature = "exact"), ..self }
    }

    /// The same engine with (`true`, the default) or without the quick stage of
    /// triangle-triangle distance (and of the queries that finish with it: within-margin,
    /// intersection, mesh leaf batches).
    ///
    /// The quick stage tries one edge pair per triangle pair and answers the pair when that
    /// candidate is certified as the closest pair; the others go on to the full fast stage
    /// (all fifteen features and contact). On nearby triangles of a mesh it answers nearly
    /// every pair for about a third of the full stage's cost. On arbitrary pairs (triangles
    /// placed independently, many intersecting) it answers few, and those it leaves open pay
    /// for both stages plus their gathering: for such batches, `quick_stage(false)` sends
    /// every pair straight to the full fast stage. THROUGHPUT.md measures both settings on
    /// both workloads.
    ///
    /// Either way every answer meets the same guarantee (the tolerance, the bound table,
    /// [`Tolerance`]). Both settings give the same bits from run to run, in every lane
    /// position and on any number of threads; between the two settings, a pair's answer can
    /// differ within that guarantee (the two stages round differently).
    ///
    /// # Example
    /// ```
    /// use tridist::Engine;
    /// let a = vec![[[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]; 100];
    /// let b = vec![[[0.2f32, 0.2, -1.0], [0.3, 0.2, 1.0], [0.2, 0.3, 1.0]]; 100]; // piercing
    /// let mut out = vec![1.0f32; 100];
    /// let counts = Engine::auto().quick_stage(false).sqdist_triangle_triangle(&a, &b, &mut out).unwrap();
    /// assert!(out.iter().all(|&d| d == 0.0));
    /// assert_eq!(counts.refined, 100); // every pair went to the full fast stage
    /// ```
    pub fn quick_stage(self, on: bool) -> Engine {
        Engine { quick: on, ..self }
    }

    /// Whether triangle-triangle distance starts with its quick stage ([`Engine::quick_stage`]).
    pub fn uses_quick_stage(&self) -> bool {
        self.quick
    }

    /// The same engine with the margin of [`Query::Within`] for [`Engine::run`]. A negative or
    /// non-finite margin makes every query return [`Error::InvalidMargin`] ([`Engine::check`]).
    pub fn margin(self, margin: f64) -> Engine {
        Engine { margin, ..self }
    }

    /// The same engine with the options of [`Query::Penalty`] for [`Engine::run`]. Options that
    /// fail [`PenaltyOptions::is_valid`] make every query return [`Error::InvalidOptions`]
    /// ([`Engine::check`]), and so do options valid in `f64` but not in the precision of the
    /// batch they are used on (a `rho` beyond `f32`'s range, say).
    pub fn penalty<T: Real>(self, o: &PenaltyOptions<T>) -> Engine {
        let c = |x: T| x.to_f64();
        let penalty = PenaltyOptions {
            rho: c(o.rho),
            reg: c(o.reg),
            tol: c(o.tol),
            max_iter: o.max_iter,
            start: o.start.map(c),
        };
        Engine { penalty: Some(penalty), ..self }
    }

    /// The error every query on this engine returns for its settings, if any: the setters
    /// never fail ([`Engine`]'s builder convention), so this is where an invalid tolerance,
    /// margin or penalty options show.
    ///
    /// # Errors
    /// [`Error::InvalidTolerance`] for a negative or NaN tolerance entry,
    /// [`Error::InvalidMargin`] for a negative or non-finite margin, [`Error::InvalidOptions`]
    /// for penalty options that fail [`PenaltyOptions::is_valid`].
    ///
    /// # Example
    /// ```
    /// use tridist::{Engine, Error};
    /// let e = Engine::auto().margin(-1.0);
    /// assert_eq!(e.check(), Err(Error::InvalidMargin));
    /// let a = [[[0.0f64, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]];
    /// let mut out = [0.0];
    /// assert_eq!(e.sqdist_triangle_triangle(&a[..], &a[..], &mut out).err(), Some(Error::InvalidMargin));
    /// assert!(e.margin(0.5).check().is_ok());
    /// ```
    pub fn check(&self) -> Result<(), Error> {
        self.tol.check()?;
        if !(self.margin.is_finite() && self.margin >= 0.0) {
            return Err(Error::InvalidMargin);
        }
        match &self.penalty {
            Some(p) if !p.is_valid() => Err(Error::InvalidOptions),
            _ => Ok(()),
        }
    }

    /// The parameters of a query in precision `T`, after [`Engine::check`]; the penalty options
    /// must be valid in `T` too.
    pub(crate) fn params<T: Real>(&self) -> Result<Params<T>, Error> {
        self.check()?;
        let penalty = self.penalty_in::<T>();
        if !penalty.is_valid() {
            return Err(Error::InvalidOptions);
        }
        Ok(self.params_with(penalty))
    }

    /// The penalty options in precision `T` (the defaults of `T` when none were set).
    fn penalty_in<T: Real>(&self) -> PenaltyOptions<T> {
        let c = T::from_f64;
        match &self.penalty {
            Some(p) => PenaltyOptions {
                rho: c(p.rho),
                reg: c(p.reg),
                tol: c(p.tol),
                max_iter: p.max_iter,
                start: p.start.map(c),
            },
            None => PenaltyOptions::<T>::default(),
        }
    }

    /// The parameters of a query in precision `T`, for an engine whose settings were checked in
    /// `T` or a narrower precision (so valid in `T` too).
    pub(crate) fn params_of_checked<T: Real>(&self) -> Params<T> {
        self.params_with(self.penalty_in::<T>())
    }

    fn params_with<T: Real>(&self, penalty: PenaltyOptions<T>) -> Params<T> {
        let u = T::UNIT_ROUNDOFF.to_f64();
        let c = T::from_f64;
        Params {
            margin: c(self.margin),
            tol_scaled: c(self.tol.scaled * u),
            tol_abs: c(self.tol.absolute),
            tol_rel: c(self.tol.relative),
            penalty: penalty.params(),
            quick: self.quick,
            exact_contacts: false,
        }
    }

    /// Whether the exact oracle is the last escalation step.
    pub(crate) fn uses_exact(&self) -> bool {
        self.exact
    }

    /// Runs `query` on pairs `a[i]`, `b[i]` (a [`Prims::One`] side pairs with every primitive
    /// of the other), writing the requested `out`puts. The typed methods below are this with
    /// fixed outputs; the margin and penalty options come from [`Engine::margin`] and
    /// [`Engine::penalty`].
    ///
    /// # Errors
    /// The engine's setting errors first ([`Engine::check`]), then [`Error::Arity`] when `KA`,
    /// `KB` are not the query's primitive sizes ([`Query::arity`]), [`Error::LengthMismatch`]
    /// when `a`, `b` and the outputs disagree in length. An empty batch is fine and writes
    /// nothing.
    ///
    /// # Returns
    /// Which path the pairs took ([`PathCounts`]).
    pub fn run<'a, T: Real, const KA: usize, const KB: usize>(
        &self,
        query: Query,
        a: impl Into<Prims<'a, T, KA>>,
        b: impl Into<Prims<'a, T, KB>>,
        out: Outputs<'_, T>,
    ) -> Result<PathCounts, Error> {
        let prm = self.params::<T>()?;
        if query.arity() != (KA, KB) {
            return Err(Error::Arity { query, expected: query.arity(), found: (KA, KB) });
        }
        let (a, b) = (a.into(), b.into());
        let n = match (a.len(), b.len()) {
            (Some(x), Some(y)) if x != y => {
                return Err(Error::LengthMismatch { what: "b", expected: x, found: y })
            }
            (Some(x), _) | (None, Some(x)) => x,
            (None, None) => 1,
        };
        let s = &out.sink;
        let lens = [
            ("sqdist", s.d.as_ref().map(|x| x.len())),
            ("distances", s.dist.as_ref().map(|x| x.len())),
            ("verdicts", s.verdict.as_ref().map(|x| x.len())),
            ("closest_points", s.cp.as_ref().map(|x| x.len())),
            ("p", s.p.as_ref().map(|x| x.len())),
            ("q", s.q.as_ref().map(|x| x.len())),
            ("intervals", s.iv.as_ref().map(|x| x.len())),
            ("iterations", s.iters.as_ref().map(|x| x.len())),
            ("certified", s.ok.as_ref().map(|x| x.len())),
        ];
        for (what, len) in lens {
            if query.is_verdict() && len.is_some() && !matches!(what, "verdicts" | "iterations" | "certified")
            {
                return Err(Error::NoSuchOutput { query, output: what });
            }
            if let Some(len) = len {
                if len != n {
                    return Err(Error::LengthMismatch { what, expected: n, found: len });
                }
            }
        }
        if self.tol.correctly_rounded && query == Query::Penalty {
            return Err(Error::Unsupported { query: "penalty", setting: "correctly rounded answers" });
        }
        let job = Job {
            query,
            a: a.src(),
            b: b.src(),
            n,
            prm,
            sink: out.sink,
            counts: PathCounts::default(),
            widen: true,
            exact: self.exact,
        };
        if self.tol.correctly_rounded && !query.is_verdict() {
            return Ok(self.run_rounded(job));
        }
        Ok(self.exec(job))
    }

    /// Runs a validated job, split across threads when asked.
    fn exec<T: Real>(&self, mut job: Job<'_, T>) -> PathCounts {
        let n = job.n;
        if self.threads <= 1 || n < Engine::MIN_PARALLEL {
            crate::arch::run(self.isa, &mut job);
            return job.counts;
        }
        // Pieces of whole chunks, many per thread, so that a thread that finishes early (or a
        // helper that wakes late) takes work from the others.
        let piece = (n.div_ceil(16 * self.threads)).div_ceil(Engine::PIECE).max(1) * Engine::PIECE;
        run_pieces(self.isa, self.threads, piece, job)
    }
}

/// The typed batch methods: each is [`Engine::run`] with fixed outputs.
macro_rules! distance_methods {
    ($($q:ident, $ka:literal, $kb:literal, $sq:ident, $cp:ident, $what:literal;)*) => {
        impl Engine {
            $(
                #[doc = concat!("Squared ", $what, " distances, `out[i]` for pair `i` ([`Query::", stringify!($q), "`]).")]
                ///
                /// # Behaviour
                /// As the single query of the same name; touching and intersecting primitives give
                /// exactly `0`, degenerate ones are the points or segments they are, NaN/inf input
                /// gives NaN for that pair only, a square beyond the largest finite value gives
                /// `+inf` (within the answer's error of that value, either `+inf` or a finite value).
                ///
                /// # Errors
                /// [`Error::LengthMismatch`] when `a`, `b` and `out` disagree in length (a
                /// [`Prims::One`] side matches any length); the engine's setting errors
                /// ([`Engine::check`]). An empty batch is fine.
                ///
                /// # Precision
                /// Within the engine's [`Tolerance`] for every certified pair (the returned
                /// [`PathCounts`] count the others); measured error per input family, variant and
                /// precision in `reports/ACCURACY.md`.
                ///
                /// # Performance
                /// Queries per second per variant, layout and precision: `reports/THROUGHPUT.md`.
                pub fn $sq<'a, T: Real>(
                    &self,
                    a: impl Into<Prims<'a, T, $ka>>,
                    b: impl Into<Prims<'a, T, $kb>>,
                    out: &mut [T],
                ) -> Result<PathCounts, Error> {
                    self.run(Query::$q, a, b, Outputs::new().sqdist(out))
                }

                #[doc = concat!("Squared ", $what, " distances and closest points ([`Query::", stringify!($q), "`]).")]
                ///
                /// # Errors
                /// As the squared-distance method, for `out`.
                pub fn $cp<'a, T: Real>(
                    &self,
                    a: impl Into<Prims<'a, T, $ka>>,
                    b: impl Into<Prims<'a, T, $kb>>,
                    out: &mut [ClosestPoints<T>],
                ) -> Result<PathCounts, Error> {
                    self.run(Query::$q, a, b, Outputs::new().closest_points(out))
                }
            )*
        }
    };
}
distance_methods! {
    SegSeg, 2, 2, sqdist_segment_segment, closest_points_segment_segment, "segment-segment";
    PointTri, 1, 3, sqdist_point_triangle, closest_point_point_triangle, "point-triangle";
    TriTri, 3, 3, sqdist_triangle_triangle, closest_points_triangle_triangle, "triangle-triangle";
    TriTriBrute, 3, 3, sqdist_triangle_triangle_brute, closest_points_triangle_triangle_brute, "brute-force triangle-triangle";
}

impl Engine {
    /// Intersection verdicts ([`Query::Intersect`]): certified separating axes first, a
    /// piercing witness for overlaps, the full distance pipeline for the rest.
    ///
    /// # Errors
    /// As [`Engine::sqdist_triangle_triangle`].
    pub fn intersect_triangle_triangle<'a, T: Real>(
        &self,
        a: impl Into<Prims<'a, T, 3>>,
        b: impl Into<Prims<'a, T, 3>>,
        out: &mut [Intersection],
    ) -> Result<PathCounts, Error> {
        self.run(Query::Intersect, a, b, Outputs::new().verdicts(out))
    }

    /// Within-margin ([`Query::Within`]): `out[i]` is the squared distance when the distance is
    /// at most `margin`, else `+inf`. Pairs whose bounding boxes are certainly farther apart than
    /// the margin skip the distance computation; the others get exactly the answer of
    /// [`Engine::sqdist_triangle_triangle`], thresholded.
    ///
    /// # Errors
    /// [`Error::InvalidMargin`] for a negative or non-finite `margin`; otherwise as
    /// [`Engine::sqdist_triangle_triangle`].
    pub fn within_margin_triangle_triangle<'a, T: Real>(
        &self,
        a: impl Into<Prims<'a, T, 3>>,
        b: impl Into<Prims<'a, T, 3>>,
        margin: T,
        out: &mut [T],
    ) -> Result<PathCounts, Error> {
        self.margin(margin.to_f64()).run(Query::Within, a, b, Outputs::new().sqdist(out))
    }

    /// Triangle-triangle distance by Krestenitis & Koziara's penalty method ([`Query::Penalty`]):
    /// a regularised Newton iteration on the barycentric parameters of both triangles, each lane
    /// iterating independently. Writes the answers (points on their triangles) and the
    /// iterations used.
    ///
    /// # Behaviour
    /// An approximation whose accuracy the caller trades for speed with [`PenaltyOptions`]; the
    /// points are brought back onto their triangles, so the distance is an upper bound, and its
    /// certified interval ([`Outputs::intervals`] through [`Engine::run`]) says how far off it
    /// may be. Never escalated. NaN input gives NaN.
    ///
    /// # Errors
    /// [`Error::InvalidOptions`]; lengths as [`Engine::closest_points_triangle_triangle`], also
    /// for `iters`.
    pub fn penalty_triangle_triangle<'a, T: Real>(
        &self,
        a: impl Into<Prims<'a, T, 3>>,
        b: impl Into<Prims<'a, T, 3>>,
        options: &PenaltyOptions<T>,
        out: &mut [ClosestPoints<T>],
        iters: &mut [u32],
    ) -> Result<PathCounts, Error> {
        self.penalty(options).run(Query::Penalty, a, b, Outputs::new().closest_points(out).iterations(iters))
    }
}
