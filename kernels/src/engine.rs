//! The engine: runs batch queries on one instruction-set variant, with a tolerance, optional
//! threads, and the outputs the caller asks for.

use std::sync::OnceLock;

use crate::algo::{Params, PenaltyParams};
use crate::drv::{Job, Sink, Src};
use crate::pose::{points, AsPoint};
use crate::{Batch, ClosestPoints, Error, Intersection, Interval, Isa, PathCounts, Point, Query, Real};

/// One side of a batch query: SoA columns (fastest for SIMD), a plain slice (AoS: the paper's
/// "non-SIMD layout"), or a single primitive broadcast against every primitive of the other side.
#[derive(Clone, Copy, Debug)]
pub enum Prims<'a, T, const K: usize> {
    /// SoA columns.
    Soa(&'a Batch<T, K>),
    /// Plain array of primitives.
    Aos(&'a [[Point<T>; K]]),
    /// One primitive against many.
    One([Point<T>; K]),
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
impl<'a, T: Real, P: AsPoint<T>, const K: usize> From<&[P; K]> for Prims<'a, T, K> {
    fn from(b: &[P; K]) -> Self {
        Prims::One(points(b))
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
    fn src<'s>(&'s self) -> Src<'s, T>
    where
        'a: 's,
    {
        match self {
            Prims::Soa(b) => Src::of_batch(b),
            Prims::Aos(s) => Src::Aos { flat: s.as_flattened().as_flattened(), k: K },
            Prims::One(p) => Src::One { flat: p.as_flattened(), k: K },
        }
    }
}

/// How good an answer must be before a batch stops working on it: the speed-for-accuracy
/// trade in one parameter.
///
/// Every query computes a certified interval `[lo, hi]` around the exact distance of each pair
/// ([`Interval`]). A pair is done when `hi - lo <= max(scaled * u * S, absolute, relative *
/// lo)` (`u` the unit roundoff of the input's precision, `S` the pair's largest absolute
/// coordinate). Otherwise it goes on: from the quick stage (triangle-triangle distance) to the
/// full fast stage and from there to the accurate stage (each gathered into full vectors; on
/// AVX-512 the quick stage's open pairs are packed from its registers instead), then, for f32
/// input, to the same algorithm in f64 on the exactly widened input, then, with the `exact`
/// feature, to the exact rational oracle. What each setting
/// guarantees, for every pair the batch reports as certified ([`PathCounts::uncertified`]
/// counts the others):
///
/// * the returned distance is within the tolerance of the exact one (squared: `sqdist` is the
///   square of a distance in `[lo, hi]`, rounded once); when the interval's ends are subnormal,
///   each may also lie up to two subnormal steps further out (the test runs on prescaled
///   coordinates; unscaling rounds each end to the subnormal grid and then one step outward),
///   so `hi - lo <= tolerance + 4 * MIN_SUBNORMAL`;
/// * an intersection verdict "disjoint" is always proven (`lo > 0`); "intersecting" means the
///   distance is at most the tolerance (exactly 0 with the `exact` feature and
///   [`Tolerance::EXACT`]);
/// * [`Tolerance::EXACT`] (all zero): every pair that is not exactly representable goes to the
///   last stage available: the exact oracle with the feature, else it stays uncertified with
///   its tightest interval (f64 for f32 input).
///
/// The tolerance is what is guaranteed, not what is aimed at: triangle-triangle distance
/// accepts an answer before its last stage (brute force) only when it is also *sharp*: its
/// distance within `u S` (quick stage) or `8 u S` (full fast stage) of the gap along its
/// direction, or a contact, or its tight interval (re-certification, accurate stage) no wider
/// than `5 u S` plus the certificate's own `12 u d` slack, so that a wrong pair of points
/// that happens to lie within a loose tolerance still goes on to the accurate stages
/// (ACCURACY.md's measured error is far below the default tolerance). Every stage of the
/// distance queries but triangle-triangle's fast one (which has the rule above) also accepts
/// an answer only when it agrees with its own closest points, `|p - q| <= sqrt(d) + 8 u S`:
/// a contact answer (0) has its points within `8 u S` of each other.
///
/// The penalty method is never escalated (the caller chose an approximation): its interval
/// says how far off it is.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct Tolerance {
    /// In units of `u * S`.
    pub scaled: f64,
    /// In the caller's units.
    pub absolute: f64,
    /// Relative to the distance (times the certified lower bound).
    pub relative: f64,
}

impl Tolerance {
    /// The default: `64 u S`. Measured: the fast stage certifies nearly every generic pair at
    /// this width (the report publishes the fractions per family), while the distance error it
    /// admits stays far below it (ACCURACY.md).
    pub const DEFAULT: Tolerance = Tolerance { scaled: 64.0, absolute: 0.0, relative: 0.0 };
    /// Nothing but exact answers are accepted (see the type docs).
    pub const EXACT: Tolerance = Tolerance { scaled: 0.0, absolute: 0.0, relative: 0.0 };

    /// `k * u * S`.
    pub const fn scaled(k: f64) -> Tolerance {
        Tolerance { scaled: k, absolute: 0.0, relative: 0.0 }
    }
    /// An absolute distance.
    pub const fn absolute(x: f64) -> Tolerance {
        Tolerance { scaled: 0.0, absolute: x, relative: 0.0 }
    }
    /// Relative to the distance.
    pub const fn relative(r: f64) -> Tolerance {
        Tolerance { scaled: 0.0, absolute: 0.0, relative: r }
    }

    fn check(&self) -> Result<(), Error> {
        let ok = |x: f64| x >= 0.0;
        if ok(self.scaled) && ok(self.absolute) && ok(self.relative) {
            Ok(())
        } else {
            Err(Error::InvalidTolerance)
        }
    }
}

impl Default for Tolerance {
    fn default() -> Self {
        Tolerance::DEFAULT
    }
}

/// Options of the penalty method ([`Engine::penalty_triangle_triangle`]): the
/// speed-for-accuracy knob of that approximation. `rho` and `reg` are relative to the pair's
/// own curvature and `tol` to its magnitude, so the same options behave the same at every scale.
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
    /// Are the options usable?
    pub fn is_valid(&self) -> bool {
        let pos = |x: T| x.is_finite() && x > T::ZERO;
        pos(self.rho)
            && pos(self.reg)
            && pos(self.tol)
            && self.max_iter >= 1
            && self.start.iter().all(|x| x.is_finite())
    }

    pub(crate) fn params(&self) -> PenaltyParams<T> {
        PenaltyParams {
            rho: self.rho,
            reg: self.reg,
            tol: self.tol,
            max_iter: self.max_iter,
            start: self.start,
        }
    }
}

/// The outputs of a batch query, any subset (each slice has one element per pair): squared
/// distances, closest points (as [`ClosestPoints`] or as two parallel slices), certified
/// intervals, intersection verdicts, penalty iterations.
///
/// # Example
/// ```
/// use tridist::{Engine, Interval, Outputs, Query};
/// let a = [[[0.0f64, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]; 3];
/// let b = [[[0.0f64, 0.0, 2.0], [1.0, 0.0, 2.0], [0.0, 1.0, 2.0]]; 3];
/// let (mut d, mut iv) = ([0.0; 3], [Interval::default(); 3]);
/// let counts = Engine::auto()
///     .run(Query::TriTri, &a[..], &b[..], Outputs::new().sqdist(&mut d).intervals(&mut iv))
///     .unwrap();
/// assert_eq!(d, [4.0; 3]);
/// assert!(iv.iter().all(|i| i.contains(2.0)));
/// assert_eq!((counts.pairs, counts.uncertified), (3, 0));
/// ```
#[derive(Default)]
pub struct Outputs<'a, T> {
    sink: Sink<'a, T>,
}

impl<'a, T: Real> Outputs<'a, T> {
    /// No outputs yet.
    pub fn new() -> Self {
        Outputs { sink: Sink::default() }
    }
    /// Squared distances (within-margin: `+inf` beyond the margin; [`Query::Intersect`]:
    /// [`Error::NoSuchOutput`], as for every distance output).
    pub fn sqdist(mut self, out: &'a mut [T]) -> Self {
        self.sink.d = Some(out);
        self
    }
    /// Squared distances and closest points.
    pub fn closest_points(mut self, out: &'a mut [ClosestPoints<T>]) -> Self {
        self.sink.cp = Some(out);
        self
    }
    /// Closest points as two parallel slices (`p` on the first primitive).
    pub fn points(mut self, p: &'a mut [Point<T>], q: &'a mut [Point<T>]) -> Self {
        self.sink.p = Some(p);
        self.sink.q = Some(q);
        self
    }
    /// Certified intervals of the distance. Not for [`Query::Intersect`] (its separating-axis
    /// test computes no distance): asking it for this, `sqdist`, `closest_points` or `points`
    /// is [`Error::NoSuchOutput`]; ask for [`Outputs::verdicts`], or run [`Query::TriTri`] for a
    /// certified distance.
    pub fn intervals(mut self, out: &'a mut [Interval<T>]) -> Self {
        self.sink.iv = Some(out);
        self
    }
    /// Intersection verdicts (any triangle query: contact within the tolerance).
    pub fn verdicts(mut self, out: &'a mut [Intersection]) -> Self {
        self.sink.verdict = Some(out);
        self
    }
    /// Iterations used (penalty method; 0 for the other queries).
    pub fn iterations(mut self, out: &'a mut [u32]) -> Self {
        self.sink.iters = Some(out);
        self
    }
}

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

/// Building an engine: every setter takes the engine by value and returns the changed one.
/// Those whose argument can be invalid ([`Engine::new`], [`Engine::tolerance`],
/// [`Engine::margin`], [`Engine::penalty`]) check it there and return `Result<Engine, Error>`,
/// so that a query never fails on a setting; the others ([`Engine::threads`],
/// [`Engine::exact`], [`Engine::quick_stage`]) cannot fail and return `Engine`.
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
    pub const WAIT_AWAKE: std::time::Duration = std::time::Duration::from_micros(200);

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

    /// The same engine with another tolerance ([`Tolerance`]).
    ///
    /// # Errors
    /// [`Error::InvalidTolerance`] for negative or NaN entries.
    pub fn tolerance(self, tol: Tolerance) -> Result<Engine, Error> {
        tol.check()?;
        Ok(Engine { tol, ..self })
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

    /// The same engine with the margin of [`Query::Within`] for [`Engine::run`].
    ///
    /// # Errors
    /// [`Error::InvalidMargin`] for a negative or non-finite margin.
    pub fn margin(self, margin: f64) -> Result<Engine, Error> {
        if !(margin.is_finite() && margin >= 0.0) {
            return Err(Error::InvalidMargin);
        }
        Ok(Engine { margin, ..self })
    }

    /// The same engine with the options of [`Query::Penalty`] for [`Engine::run`].
    ///
    /// # Errors
    /// [`Error::InvalidOptions`] when [`PenaltyOptions::is_valid`] fails.
    pub fn penalty<T: Real>(self, o: &PenaltyOptions<T>) -> Result<Engine, Error> {
        if !o.is_valid() {
            return Err(Error::InvalidOptions);
        }
        let c = |x: T| x.to_f64();
        let penalty = PenaltyOptions {
            rho: c(o.rho),
            reg: c(o.reg),
            tol: c(o.tol),
            max_iter: o.max_iter,
            start: o.start.map(c),
        };
        Ok(Engine { penalty: Some(penalty), ..self })
    }

    pub(crate) fn params<T: Real>(&self) -> Params<T> {
        let u = T::UNIT_ROUNDOFF.to_f64();
        let c = T::from_f64;
        let penalty = match &self.penalty {
            Some(p) => PenaltyOptions {
                rho: c(p.rho),
                reg: c(p.reg),
                tol: c(p.tol),
                max_iter: p.max_iter,
                start: p.start.map(c),
            },
            None => PenaltyOptions::<T>::default(),
        };
        Params {
            margin: c(self.margin),
            tol_scaled: c(self.tol.scaled * u),
            tol_abs: c(self.tol.absolute),
            tol_rel: c(self.tol.relative),
            penalty: penalty.params(),
            quick: self.quick,
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
    /// [`Error::Arity`] when `KA`, `KB` are not the query's primitive sizes
    /// ([`Query::arity`]), [`Error::LengthMismatch`] when `a`, `b` and the outputs disagree in
    /// length. An empty batch is fine and writes nothing.
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
            ("verdicts", s.verdict.as_ref().map(|x| x.len())),
            ("closest_points", s.cp.as_ref().map(|x| x.len())),
            ("p", s.p.as_ref().map(|x| x.len())),
            ("q", s.q.as_ref().map(|x| x.len())),
            ("intervals", s.iv.as_ref().map(|x| x.len())),
            ("iterations", s.iters.as_ref().map(|x| x.len())),
        ];
        for (what, len) in lens {
            if query.is_verdict() && len.is_some() && !matches!(what, "verdicts" | "iterations") {
                return Err(Error::NoSuchOutput { query, output: what });
            }
            if let Some(len) = len {
                if len != n {
                    return Err(Error::LengthMismatch { what, expected: n, found: len });
                }
            }
        }
        let job = Job {
            query,
            a: a.src(),
            b: b.src(),
            n,
            prm: self.params::<T>(),
            sink: out.sink,
            counts: PathCounts::default(),
            widen: true,
            exact: self.exact,
        };
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

/// The pairs of a split batch not taken yet, `front..back`, and their outputs.
struct Left<'a, T> {
    front: usize,
    back: usize,
    sink: Sink<'a, T>,
}

/// Runs `job` in pieces of `piece` pairs (the last one shorter) on `threads` threads
/// ([`together`]), each taking the next piece as it finishes one: the calling thread from the
/// front, the helpers from the back. A batch run again (a planner's next step, a benchmark's
/// next round) then leaves about the same half in each core's cache; taken in one order by
/// both, the pieces went to either core. With the caller's wait of [`together`], 2 threads
/// answered 4000 nearby Armadillo pairs at 1.24-1.61x one thread's speed in one order and
/// 1.45-1.75x from the two ends (`spin tri_tri arm_nearby f32 avx2fma 1 4000 1|2`, two copies
/// of each build alternated twice; the machine is shared and noisy).
///
/// A piece's job is made by the thread that takes it, its outputs split off the ones left
/// under the lock, and each thread adds up its own path counts. The jobs had been made in a
/// vector by the caller before the split and their counts summed after it: 0.63-0.75 µs and
/// about 0.8 µs of a 23 µs batch on two threads (0.25-0.33 µs to make them on one), the
/// helper's jobs written on one core and read on the other (throwaway timestamps, `spin
/// tri_tri arm_nearby f32 avx2fma 1 4000 2`, 2026-11-29, the AMD EPYC). Without that vector,
/// with the driver's spare open-pair lists (`drv.rs`, `Pending`) and the caller's spinning
/// wait ([`together`]): 143.7 -> 157.0 M/s on two threads (medians), faster in 10 of 10 rounds
/// alternated with the parent's binary (the machine noisy), and two threads over one 1.40-1.77x (median
/// 1.59x) -> 1.54-1.80x (1.66x) in 8 rounds of both builds alternated; later, quieter,
/// 1.69-1.81x (1.75x). Pieces shrinking towards the end (each a quarter of what was left,
/// down to 256 pairs) were no better this time either: 1.63-1.89x (1.74x) in those 8 rounds.
fn run_pieces<T: Real>(isa: Isa, threads: usize, piece: usize, job: Job<'_, T>) -> PathCounts {
    use std::sync::Mutex;
    let Job { query, a, b, n, prm, sink, widen, exact, .. } = job;
    let left = Mutex::new(Left { front: 0, back: n, sink });
    let total = Mutex::new(PathCounts::default());
    together(threads.min(n.div_ceil(piece)), &|caller| {
        let mut mine = PathCounts::default();
        loop {
            let (start, len, sink) = {
                let mut l = left.lock().unwrap_or_else(|e| e.into_inner());
                if l.front >= l.back {
                    break;
                }
                let rest = std::mem::take(&mut l.sink);
                // the first piece left, or the last one (the pieces start at multiples of
                // `piece`: `front` is one, and `back` is one or `n`)
                let start = if caller { l.front } else { (l.back - 1) / piece * piece };
                let len = if caller { piece.min(l.back - l.front) } else { l.back - start };
                let (x, y) = rest.split_at(if caller { len } else { start - l.front });
                let (sink, rest) = if caller { (x, y) } else { (y, x) };
                l.sink = rest;
                if caller {
                    l.front += len;
                } else {
                    l.back = start;
                }
                (start, len, sink)
            };
            let mut job = Job {
                query,
                a: a.from(start),
                b: b.from(start),
                n: len,
                prm,
                sink,
                counts: PathCounts::default(),
                widen,
                exact,
            };
            crate::arch::run(isa, &mut job);
            mine.add(&job.counts);
        }
        total.lock().unwrap_or_else(|e| e.into_inner()).add(&mine);
    });
    total.into_inner().unwrap_or_else(|e| e.into_inner())
}

/// `f` on every item, on up to `threads` threads ([`together`]), each thread with its own
/// state made by `init`; results in item order.
pub(crate) fn par_map_init<I: Sync, St, R: Send>(
    threads: usize,
    items: &[I],
    init: impl Fn() -> St + Sync + Send,
    f: impl Fn(&mut St, &I) -> R + Sync + Send,
) -> Vec<R> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Mutex;
    let next = AtomicUsize::new(0);
    let out: Mutex<Vec<Option<R>>> = Mutex::new((0..items.len()).map(|_| None).collect());
    together(threads.min(items.len()), &|_| {
        let mut st = None;
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            let Some(item) = items.get(i) else { break };
            let r = f(st.get_or_insert_with(&init), item);
            out.lock().unwrap_or_else(|e| e.into_inner())[i] = Some(r);
        }
    });
    out.into_inner().unwrap_or_else(|e| e.into_inner()).into_iter().flatten().collect()
}

/// Runs `work` on `threads` threads at once, the calling thread one of them (`work(true)`; the
/// helpers run `work(false)`): it neither waits idle for the others to start nor sleeps while
/// they finish. The helpers come from a persistent pool of `threads - 1` with the `rayon`
/// feature, scoped threads started per call without it. Helpers the system refuses to start
/// are left out: the threads that run take their pieces (the caller alone at worst), with the
/// same answers, instead of a panic.
///
/// Done with its share, the caller waits for the helpers awake ([`Engine::WAIT_AWAKE`]:
/// spinning for its first 10 µs, the imbalance between two threads' last pieces of a small
/// batch, then yielding its core to any thread that needs it) before the pool's own wait,
/// which sleeps. (Yielding from the start, each look at the helpers was a system call; the
/// spin's own share of the gain above was within the noise: 153.8 -> 157.6 M/s, 5 of 8
/// rounds.)
/// Asleep, it needed waking when the last helper finished, and the helpers, idle meanwhile, had gone to sleep
/// too by the time the next batch came: 2 threads answered 4000 nearby Armadillo pairs (30 µs
/// batches) at 0.88-1.26x one thread's speed, 1.24-1.61x with the wait alone and 1.45-1.80x
/// with the two ends of [`run_pieces`] as well (`spin tri_tri arm_nearby f32 avx2fma 1 4000
/// 1|2`, copies of each build alternated; the machine is shared and noisy).
fn together(threads: usize, work: &(dyn Fn(bool) + Sync)) {
    if threads <= 1 {
        return work(true);
    }
    #[cfg(feature = "rayon")]
    {
        use std::sync::atomic::{AtomicUsize, Ordering};
        /// How long the caller's wait spins before it yields.
        const SPIN: std::time::Duration = std::time::Duration::from_micros(10);
        let done = AtomicUsize::new(0);
        let done = &done;
        let Some(pool) = pool(threads - 1) else {
            return work(true);
        };
        pool.in_place_scope(|s| {
            for _ in 1..threads {
                s.spawn(move |_| {
                    work(false);
                    done.fetch_add(1, Ordering::Release);
                });
            }
            work(true);
            let t0 = std::time::Instant::now();
            while done.load(Ordering::Acquire) < threads - 1 {
                let waited = t0.elapsed();
                if waited >= Engine::WAIT_AWAKE {
                    break;
                }
                if waited < SPIN {
                    std::hint::spin_loop();
                } else {
                    std::thread::yield_now();
                }
            }
        });
    }
    #[cfg(not(feature = "rayon"))]
    std::thread::scope(|s| {
        for _ in 1..threads {
            if refused() || std::thread::Builder::new().spawn_scoped(s, || work(false)).is_err() {
                break;
            }
        }
        work(true);
    });
}

/// Whether starting threads is refused, as a system out of threads would: in the unit tests,
/// on request, to test that batches still complete; never otherwise.
fn refused() -> bool {
    #[cfg(test)]
    return tests::REFUSE_THREADS.load(std::sync::atomic::Ordering::Relaxed);
    #[cfg(not(test))]
    false
}

/// A persistent pool per thread count, made on first use; `None` when the system refuses its
/// threads (tried again at the next call).
#[cfg(feature = "rayon")]
fn pool(threads: usize) -> Option<std::sync::Arc<rayon::ThreadPool>> {
    use std::sync::{Arc, Mutex};
    type Pools = Mutex<Vec<(usize, Arc<rayon::ThreadPool>)>>;
    static POOLS: OnceLock<Pools> = OnceLock::new();
    if refused() {
        return None;
    }
    let mut pools = POOLS.get_or_init(|| Mutex::new(Vec::new())).lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, p)) = pools.iter().find(|(n, _)| *n == threads) {
        return Some(p.clone());
    }
    let p = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(|i| format!("tridist-{i}"))
        .build()
        .ok()?;
    let p = Arc::new(p);
    pools.push((threads, p.clone()));
    Some(p)
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
                /// gives NaN for that pair only, an overflowing square gives `+inf`.
                ///
                /// # Errors
                /// [`Error::LengthMismatch`] when `a`, `b` and `out` disagree in length (a
                /// [`Prims::One`] side matches any length). An empty batch is fine.
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
    /// [`Error::InvalidMargin`] for a negative or non-finite margin; lengths as
    /// [`Engine::sqdist_triangle_triangle`].
    pub fn within_margin_triangle_triangle<'a, T: Real>(
        &self,
        a: impl Into<Prims<'a, T, 3>>,
        b: impl Into<Prims<'a, T, 3>>,
        margin: T,
        out: &mut [T],
    ) -> Result<PathCounts, Error> {
        self.margin(margin.to_f64())?.run(Query::Within, a, b, Outputs::new().sqdist(out))
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
        self.penalty(options)?.run(Query::Penalty, a, b, Outputs::new().closest_points(out).iterations(iters))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicBool, Ordering};

    /// Set by [`a_system_out_of_threads_still_answers_every_pair`] only.
    pub(super) static REFUSE_THREADS: AtomicBool = AtomicBool::new(false);

    #[test]
    fn a_system_out_of_threads_still_answers_every_pair() {
        // pairs of parallel triangles overlapping in plan, 13 heights apart: each distance exact
        let n = 3 * Engine::MIN_PARALLEL + 77;
        let tri = |z: f64, s: f64| [[0.0, 0.0, z], [s, 0.0, z], [0.0, s, z]];
        let a: Vec<_> = (0..n).map(|i| tri(0.0, 1.0 + (i % 7) as f64)).collect();
        let b: Vec<_> = (0..n).map(|i| tri(0.5 + (i % 13) as f64, 2.0)).collect();
        let mut one = vec![f64::NAN; n];
        Engine::auto().sqdist_triangle_triangle(&a, &b, &mut one).unwrap();
        REFUSE_THREADS.store(true, Ordering::Relaxed);
        let mut split = vec![f64::NAN; n];
        let r = Engine::auto().threads(3).sqdist_triangle_triangle(&a, &b, &mut split);
        REFUSE_THREADS.store(false, Ordering::Relaxed);
        r.unwrap();
        for i in 0..n {
            let dz = 0.5 + (i % 13) as f64;
            assert_eq!(one[i], dz * dz, "pair {i}");
            assert_eq!(split[i].to_bits(), one[i].to_bits(), "pair {i}");
        }
    }

    /// Every line of the crate's docs that states the default tolerance states the one
    /// [`Tolerance::DEFAULT`] has (two lines said 32 where the code has 64).
    #[test]
    fn the_docs_state_the_default_tolerance() {
        let want = format!("`{} u S`", Tolerance::DEFAULT.scaled);
        let mut stated = 0;
        for (file, text) in [
            ("lib.rs", include_str!("lib.rs")),
            ("single.rs", include_str!("single.rs")),
            ("engine.rs", include_str!("engine.rs")),
        ] {
            for (n, line) in text.lines().enumerate() {
                if line.contains("default") && line.contains(" u S`") && line.trim_start().starts_with("//") {
                    assert!(line.contains(&want), "{file}:{}: {line}", n + 1);
                    stated += 1;
                }
            }
        }
        assert!(stated >= 3, "{stated} lines state the default");
    }
}
