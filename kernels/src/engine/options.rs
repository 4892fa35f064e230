//! What a batch query is given: its primitives ([`Prims`]), the [`Tolerance`] it must meet,
//! the penalty method's options and the [`Outputs`] asked for.

use crate::algo::PenaltyParams;
use crate::drv::Sink;
use crate::drv::Src;
use crate::pose::points;
use crate::pose::AsPoint;
use crate::Batch;
use crate::ClosestPoints;
use crate::Error;
use crate::Intersection;
use crate::Interval;
use crate::Point;
use crate::Real;

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
    pub(super) fn len(&self) -> Option<usize> {
        match self {
            Prims::Soa(b) => Some(b.len()),
            Prims::Aos(s) => Some(s.len()),
            Prims::One(_) => None,
        }
    }
    pub(super) fn src<'s>(&'s self) -> Src<'s, T>
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
/// guarantees, for every pair the batch reports as certified ([`PathCounts::uncertified`](crate::PathCounts::uncertified)
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
///
/// # Correctly rounded answers
/// [`Tolerance::CORRECTLY_ROUNDED`] is the top of the trade: every squared distance returned
/// (segment-segment, point-triangle, triangle-triangle and its brute force, within-margin) is
/// `RN(D*)`, the exact squared distance of the primitives as given rounded to nearest, ties to
/// even, in the input's precision, including subnormal results and `+inf` beyond the largest
/// finite value; so it is the same bits on every CPU, variant, layout and thread count. Each
/// pair is answered in f64 (f32 input exactly widened) and decided from its certified
/// interval when both ends of the squares' interval round to one value; the others go to the
/// exact oracle (feature `exact`). Without the oracle (feature off, or [`Engine::exact`](crate::Engine::exact)`(false)`)
/// an undecided pair is answered with its f64 answer rounded once, marked uncertified and
/// counted in [`PathCounts::undecided`](crate::PathCounts::undecided): never passed off as correctly rounded. In
/// practice f32 input is decided in f64 for all but pairs far closer than their size (the
/// report gives the fractions per family); f64 input needs the oracle for most pairs.
///
/// * Within-margin keeps a pair when its correctly rounded square is at most
///   `margin * margin` rounded in the input's precision.
/// * Closest points are those of the answer that decided the pair, rounded once: on their
///   primitives within the f64 answer's guarantee (or the oracle's exact points rounded), not
///   the same bits on every variant. Intervals are the f64 ones rounded outward.
/// * Intersection verdicts ([`Query::Intersect`](crate::Query::Intersect)) are decided as under
///   [`Tolerance::EXACT`], and so are the mesh queries' decisions (contacts, clearance,
///   intersection). [`Engine::mesh_distance`](crate::Engine::mesh_distance) returns the
///   correctly rounded minimum over all triangle pairs, and
///   [`Engine::mesh_closest_point`](crate::Engine::mesh_closest_point) over all triangles, or
///   [`Error::Undecided`](crate::Error::Undecided) when that needs the oracle. The penalty
///   method, an approximation, refuses the mode
///   ([`Error::Unsupported`](crate::Error::Unsupported)).
///
/// * Distances ([`Outputs::distances`], [`Answer::distance`](crate::Answer::distance)) are
///   `RN(sqrt(D*))`, decided on their own in the same way (both ends of the distance's
///   interval round to one value, or the oracle's exact square root); the square root of
///   `RN(D*)` is rounded twice and can be an ulp off it. A pair asked for both is certified
///   when both are decided.
/// * [`Engine::single`](crate::Engine::single) runs the mode as a batch of one.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct Tolerance {
    /// In units of `u * S`.
    pub scaled: f64,
    /// In the caller's units.
    pub absolute: f64,
    /// Relative to the distance (times the certified lower bound).
    pub relative: f64,
    /// Every squared distance and distance correctly rounded
    /// ([`Tolerance::CORRECTLY_ROUNDED`]); the widths above are then unused.
    pub correctly_rounded: bool,
}

impl Tolerance {
    /// The default: `64 u S`. Measured: the fast stage certifies nearly every generic pair at
    /// this width (the report publishes the fractions per family), while the distance error it
    /// admits stays far below it (ACCURACY.md).
    pub const DEFAULT: Tolerance =
        Tolerance { scaled: 64.0, absolute: 0.0, relative: 0.0, correctly_rounded: false };
    /// Nothing but exact answers are accepted (see the type docs).
    pub const EXACT: Tolerance =
        Tolerance { scaled: 0.0, absolute: 0.0, relative: 0.0, correctly_rounded: false };
    /// Every squared distance and distance is the exact one correctly rounded (see the type
    /// docs, "Correctly rounded answers").
    pub const CORRECTLY_ROUNDED: Tolerance =
        Tolerance { scaled: 0.0, absolute: 0.0, relative: 0.0, correctly_rounded: true };

    /// `k * u * S`.
    pub const fn scaled(k: f64) -> Tolerance {
        Tolerance { scaled: k, absolute: 0.0, relative: 0.0, correctly_rounded: false }
    }
    /// An absolute distance.
    pub const fn absolute(x: f64) -> Tolerance {
        Tolerance { scaled: 0.0, absolute: x, relative: 0.0, correctly_rounded: false }
    }
    /// Relative to the distance.
    pub const fn relative(r: f64) -> Tolerance {
        Tolerance { scaled: 0.0, absolute: 0.0, relative: r, correctly_rounded: false }
    }

    pub(super) fn check(&self) -> Result<(), Error> {
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

/// Options of the penalty method ([`Engine::penalty_triangle_triangle`](crate::Engine::penalty_triangle_triangle)): the
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
    pub(super) sink: Sink<'a, T>,
}

impl<'a, T: Real> Outputs<'a, T> {
    /// No outputs yet.
    pub fn new() -> Self {
        Outputs { sink: Sink::default() }
    }
    /// Squared distances (within-margin: `+inf` beyond the margin; [`Query::Intersect`](crate::Query::Intersect):
    /// [`Error::NoSuchOutput`], as for every distance output).
    pub fn sqdist(mut self, out: &'a mut [T]) -> Self {
        self.sink.d = Some(out);
        self
    }
    /// Distances (within-margin: `+inf` beyond the margin; not for
    /// [`Query::Intersect`](crate::Query::Intersect), as every distance output).
    ///
    /// Under every tolerance but one, the square root of the squared distance (one more
    /// rounding: within the square's measured error plus half an ulp of the distance; `+inf`
    /// where the square overflows `T`, though the distance may not). Under
    /// [`Tolerance::CORRECTLY_ROUNDED`](crate::Tolerance::CORRECTLY_ROUNDED) it is
    /// `RN(sqrt(D*))`, the exact distance rounded to nearest (ties to even) in the input's
    /// precision (finite where the square overflows), decided on its own: not the square root
    /// of the correctly rounded square, which can differ from it by an ulp. A pair is certified in that mode when every rounded
    /// output asked for (square and distance) is decided.
    pub fn distances(mut self, out: &'a mut [T]) -> Self {
        self.sink.dist = Some(out);
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
    /// Certified intervals of the distance. Not for [`Query::Intersect`](crate::Query::Intersect) (its separating-axis
    /// test computes no distance): asking it for this, `sqdist`, `closest_points` or `points`
    /// is [`Error::NoSuchOutput`]; ask for [`Outputs::verdicts`], or run [`Query::TriTri`](crate::Query::TriTri) for a
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
    /// Whether each pair's answer met the tolerance: `false` for the pairs
    /// [`PathCounts::uncertified`](crate::PathCounts::uncertified) counts (and, under
    /// [`Tolerance::CORRECTLY_ROUNDED`], those [`PathCounts::undecided`](crate::PathCounts::undecided)
    /// counts: their square is not known to be correctly rounded), and for non-finite input.
    pub fn certified(mut self, out: &'a mut [bool]) -> Self {
        self.sink.ok = Some(out);
        self
    }
}
