//! The last escalation step (feature `exact`): the exact rational oracle (`tridist-oracle`,
//! GMP), for pairs that no floating-point stage could certify within the tolerance. Its answer
//! is the correctly rounded squared distance and distance, the exact closest points rounded,
//! and an interval a few ulps wide around the exact distance.

use tridist_oracle::{exact_point, point_triangle, round, segment_segment, triangle_triangle, P3};

use crate::real::{Precision, Real};
use crate::types::Point;

/// One exact answer, rounded to `T`.
pub(crate) struct ExactLane<T> {
    pub d: T,
    /// The distance, correctly rounded (not the square root of `d`).
    pub dist: T,
    pub p: Point<T>,
    pub q: Point<T>,
    pub lo: T,
    pub hi: T,
}

fn to_t<T: Real>(x: &rug::Rational) -> T {
    match T::PRECISION {
        Precision::F32 => T::from_f64(round::to_f32(x) as f64),
        Precision::F64 => T::from_f64(round::to_f64(x)),
    }
}

/// The exact answer for primitives of `ka` and `kb` points (`None` for non-finite input).
pub(crate) fn answer<T: Real>(
    ka: usize,
    a: &[Point<T>; 3],
    kb: usize,
    b: &[Point<T>; 3],
) -> Option<ExactLane<T>> {
    let ex = |p: &Point<T>| exact_point(&p.map(|x| x.to_f64())).ok();
    let pa: Vec<P3> = a[..ka].iter().map(ex).collect::<Option<_>>()?;
    let pb: Vec<P3> = b[..kb].iter().map(ex).collect::<Option<_>>()?;
    let r = match (ka, kb) {
        (2, 2) => segment_segment(&[pa[0].clone(), pa[1].clone()], &[pb[0].clone(), pb[1].clone()]),
        (1, 3) => point_triangle(&pa[0], &[pb[0].clone(), pb[1].clone(), pb[2].clone()]),
        _ => triangle_triangle(
            &[pa[0].clone(), pa[1].clone(), pa[2].clone()],
            &[pb[0].clone(), pb[1].clone(), pb[2].clone()],
        ),
    };
    let d: T = to_t(&r.d2);
    // sqrt is correctly rounded: one step outward from the square roots of the outward
    // rounded squares bounds the exact distance.
    let dq = rug::Rational::from_f64(d.to_f64());
    let d_lo = match &dq {
        Some(x) if *x > r.d2 => d.step(false),
        None => T::MAX,
        _ => d,
    };
    let d_hi = match &dq {
        Some(x) if *x < r.d2 => d.step(true),
        _ => d,
    };
    let lo = if d_lo > T::ZERO { d_lo.sqrt().step(false) } else { T::ZERO };
    let lo = if lo < T::ZERO { T::ZERO } else { lo };
    let hi = d_hi.sqrt().step(true);
    let pt = |x: &P3| [to_t(&x[0]), to_t(&x[1]), to_t(&x[2])];
    let dist = match T::PRECISION {
        Precision::F32 => round::sqrt_to_f32(&r.d2).map(|x| x as f64),
        Precision::F64 => round::sqrt_to_f64(&r.d2),
    };
    let dist = T::from_f64(dist?);
    Some(ExactLane { d, dist, p: pt(&r.p), q: pt(&r.q), lo, hi })
}
