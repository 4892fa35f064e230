//! Single queries on plain arrays (or any [`AsPoint`] type): the same stages, certificate and
//! escalation as a batch of one, on the scalar kernels, without batch set-up. They use the
//! default [`crate::Tolerance`] (and the exact oracle when built with the `exact` feature);
//! [`Engine::single`] takes an engine's settings.

use crate::pose::AsPoint;
use crate::{
    ClosestPoints, Engine, Error, Intersection, Interval, Outputs, PenaltyOptions, Point, Prims, Proximity,
    Query, Real,
};

/// Everything a single query answers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Answer<T> {
    /// Squared distance and closest points (within-margin: `+inf` beyond the margin).
    pub closest: ClosestPoints<T>,
    /// The distance: the square root of `closest.sqdist`, except under
    /// [`crate::Tolerance::CORRECTLY_ROUNDED`], where it is the exact distance correctly
    /// rounded (see [`crate::Outputs::distances`]).
    pub distance: T,
    /// Certified interval of the distance.
    pub interval: Interval<T>,
    /// Intersection verdict (contact within the tolerance).
    pub verdict: Intersection,
    /// Is the interval within the tolerance? (Under [`crate::Tolerance::CORRECTLY_ROUNDED`]:
    /// are the square and the distance both decided?)
    pub certified: bool,
    /// Penalty-method iterations (0 for the other queries).
    pub iterations: u32,
}

impl Engine {
    /// One query on one pair with this engine's tolerance, margin and penalty options, on the
    /// scalar kernels (no batch set-up): `a` and `b` hold the points of each primitive.
    ///
    /// # Errors
    /// [`Error::Arity`] when the slices do not hold the query's points ([`Query::arity`]);
    /// the engine's setting errors ([`Engine::check`]).
    ///
    /// # Example
    /// ```
    /// use tridist::{Engine, Query};
    /// let a = [[0.0f64, 0.0, 0.0], [1.0, 0.0, 0.0]];
    /// let b = [[0.5f64, 1.0, -1.0], [0.5, 1.0, 1.0]];
    /// let r = Engine::scalar().single(Query::SegSeg, &a, &b).unwrap();
    /// assert_eq!(r.closest.sqdist, 1.0);
    /// assert!(r.certified && r.interval.contains(1.0));
    /// ```
    pub fn single<T: Real, P: AsPoint<T>>(&self, query: Query, a: &[P], b: &[P]) -> Result<Answer<T>, Error> {
        if (a.len(), b.len()) != query.arity() {
            return Err(Error::Arity { query, expected: query.arity(), found: (a.len(), b.len()) });
        }
        let pad = |s: &[P]| -> [Point<T>; 3] {
            let f = |k: usize| s[if k < s.len() { k } else { 0 }].to_point();
            [f(0), f(1), f(2)]
        };
        let prm = self.params::<T>()?;
        let (a, b) = (pad(a), pad(b));
        if self.current_tolerance().correctly_rounded && !query.is_verdict() {
            return self.single_rounded(query, &a, &b);
        }
        let l = crate::drv::single(query, &a, &b, &prm, self.uses_exact());
        Ok(Answer {
            closest: ClosestPoints { sqdist: l.d, p: l.p, q: l.q },
            distance: l.d.sqrt(),
            interval: Interval { lo: l.lo, hi: l.hi },
            verdict: l.verdict(),
            certified: l.ok,
            iterations: l.it,
        })
    }
}

impl Engine {
    /// [`Engine::single`] under [`crate::Tolerance::CORRECTLY_ROUNDED`]: a batch of one (the
    /// mode decides pairs in blocks, with its own escalation).
    fn single_rounded<T: Real>(
        &self,
        query: Query,
        a: &[Point<T>; 3],
        b: &[Point<T>; 3],
    ) -> Result<Answer<T>, Error> {
        let (mut cp, mut dist, mut iv) = ([ClosestPoints::default()], [T::ZERO], [Interval::default()]);
        let (mut verdict, mut ok, mut it) = ([Intersection::Invalid], [false], [0u32]);
        let out = Outputs::new()
            .closest_points(&mut cp)
            .distances(&mut dist)
            .intervals(&mut iv)
            .verdicts(&mut verdict)
            .certified(&mut ok)
            .iterations(&mut it);
        match query.arity() {
            (2, 2) => self.run(query, Prims::One([a[0], a[1]]), Prims::One([b[0], b[1]]), out),
            (1, 3) => self.run(query, Prims::One([a[0]]), Prims::One(*b), out),
            _ => self.run(query, Prims::One(*a), Prims::One(*b), out),
        }?;
        Ok(Answer {
            closest: cp[0],
            distance: dist[0],
            interval: iv[0],
            verdict: verdict[0],
            certified: ok[0],
            iterations: it[0],
        })
    }
}

fn one<T: Real, P: AsPoint<T>>(query: Query, a: &[P], b: &[P]) -> Answer<T> {
    Engine::scalar().single(query, a, b).unwrap_or_else(|_| unreachable!("arity fixed by the signature"))
}

/// Squared distance between two triangles.
///
/// # Behaviour
/// A fast straight-line stage (nine edge pairs with accurately rounded cross products, the
/// vertex-face projections, a piercing test) certified by a rigorous interval; pairs it cannot
/// certify within the default [`crate::Tolerance`] get PQP's TriDist (Larsen et al.) with
/// certified early exits and, if needed, f64 (for f32 input) and the exact oracle (feature
/// `exact`). Intersecting or touching triangles give `0`; degenerate triangles are the segments
/// or points they are; NaN/inf input gives NaN; an overflowing result gives `+inf`.
///
/// # Precision
/// Within the default tolerance (`64 u S`) whenever certified; measured errors per input family
/// in `reports/ACCURACY.md`, bounds enforced by the test suite.
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
pub fn sqdist_triangle_triangle<T: Real, P: AsPoint<T>>(a: &[P; 3], b: &[P; 3]) -> T {
    one(Query::TriTri, a, b).closest.sqdist
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
pub fn closest_points_triangle_triangle<T: Real, P: AsPoint<T>>(a: &[P; 3], b: &[P; 3]) -> ClosestPoints<T> {
    one(Query::TriTri, a, b).closest
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
pub fn sqdist_triangle_triangle_brute<T: Real, P: AsPoint<T>>(a: &[P; 3], b: &[P; 3]) -> T {
    one(Query::TriTriBrute, a, b).closest.sqdist
}

/// Brute-force squared distance with closest points.
pub fn closest_points_triangle_triangle_brute<T: Real, P: AsPoint<T>>(
    a: &[P; 3],
    b: &[P; 3],
) -> ClosestPoints<T> {
    one(Query::TriTriBrute, a, b).closest
}

/// Do two triangles touch or overlap?
///
/// # Behaviour
/// [`Intersection::Disjoint`] only when a separating direction is proven beyond rounding;
/// [`Intersection::Intersecting`] when they touch, overlap, or are within the default tolerance
/// of touching; [`Intersection::Invalid`] when a coordinate is NaN or infinite.
///
/// # Example
/// ```
/// use tridist::Intersection;
/// let a = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// let b = [[1.0f32, 0.0, 0.0], [2.0, 0.0, 0.0], [1.0, 1.0, 0.0]]; // shares a vertex
/// assert_eq!(tridist::intersect_triangle_triangle(&a, &b), Intersection::Intersecting);
/// let c = [[0.0f32, 0.0, f32::NAN], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// assert_eq!(tridist::intersect_triangle_triangle(&a, &c), Intersection::Invalid);
/// ```
pub fn intersect_triangle_triangle<T: Real, P: AsPoint<T>>(a: &[P; 3], b: &[P; 3]) -> Intersection {
    one(Query::Intersect, a, b).verdict
}

/// Is the distance at most `margin`, and if so, what is its square?
///
/// # Behaviour
/// [`Proximity::Within`] with the squared distance of [`sqdist_triangle_triangle`] when the
/// distance is at most `margin`, [`Proximity::Beyond`] when farther (bounding boxes farther
/// apart than the margin are rejected without the distance computation),
/// [`Proximity::Invalid`] for non-finite input.
///
/// # Errors
/// [`Error::InvalidMargin`] when `margin` is negative or not finite.
///
/// # Example
/// ```
/// use tridist::Proximity;
/// let a = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// let b = [[0.0f32, 0.0, 2.0], [1.0, 0.0, 2.0], [0.0, 1.0, 2.0]];
/// assert_eq!(tridist::within_margin_triangle_triangle(&a, &b, 3.0), Ok(Proximity::Within(4.0)));
/// assert_eq!(tridist::within_margin_triangle_triangle(&a, &b, 1.0), Ok(Proximity::Beyond));
/// ```
pub fn within_margin_triangle_triangle<T: Real, P: AsPoint<T>>(
    a: &[P; 3],
    b: &[P; 3],
    margin: T,
) -> Result<Proximity<T>, Error> {
    let r = Engine::scalar().margin(margin.to_f64()).single(Query::Within, a, b)?;
    let d = r.closest.sqdist;
    Ok(if d.is_nan() {
        Proximity::Invalid
    } else if d == T::INFINITY {
        Proximity::Beyond
    } else {
        Proximity::Within(d)
    })
}

/// Squared distance between two segments (Ericson, *Real-Time Collision Detection* 5.1.9),
/// with zero-length segments treated as points.
///
/// # Example
/// ```
/// let a = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0]];
/// let b = [[0.5f32, 1.0, -1.0], [0.5, 1.0, 1.0]];
/// assert_eq!(tridist::sqdist_segment_segment(&a, &b), 1.0);
/// ```
pub fn sqdist_segment_segment<T: Real, P: AsPoint<T>>(a: &[P; 2], b: &[P; 2]) -> T {
    one(Query::SegSeg, a, b).closest.sqdist
}

/// Squared distance and closest points of two segments.
pub fn closest_points_segment_segment<T: Real, P: AsPoint<T>>(a: &[P; 2], b: &[P; 2]) -> ClosestPoints<T> {
    one(Query::SegSeg, a, b).closest
}

/// Squared distance from a point to a triangle (Ericson 5.1.5). Degenerate triangles are
/// treated as their segments or point.
///
/// # Example
/// ```
/// let t = [[0.0f64, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// assert_eq!(tridist::sqdist_point_triangle(&[0.25, 0.25, 2.0], &t), 4.0);
/// ```
pub fn sqdist_point_triangle<T: Real, P: AsPoint<T>>(p: &P, t: &[P; 3]) -> T {
    one(Query::PointTri, core::slice::from_ref(p), t).closest.sqdist
}

/// Squared distance from a point to a triangle and the closest point on it (`q`; `p` is the
/// query point).
pub fn closest_point_point_triangle<T: Real, P: AsPoint<T>>(p: &P, t: &[P; 3]) -> ClosestPoints<T> {
    one(Query::PointTri, core::slice::from_ref(p), t).closest
}

/// Triangle distance by the penalty method (see [`Engine::penalty_triangle_triangle`]): the
/// answer and the iterations used.
///
/// # Errors
/// [`Error::InvalidOptions`] when the options are out of range.
pub fn penalty_triangle_triangle<T: Real, P: AsPoint<T>>(
    a: &[P; 3],
    b: &[P; 3],
    options: &PenaltyOptions<T>,
) -> Result<(ClosestPoints<T>, u32), Error> {
    let r = Engine::scalar().penalty(options).single(Query::Penalty, a, b)?;
    Ok((r.closest, r.iterations))
}
