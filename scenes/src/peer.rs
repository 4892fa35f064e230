//! The peer a Rust user would pick today: parry3d (f32) and parry3d-f64,
//! `query::distance` on two `Triangle` shapes at identity poses (GJK on support maps). Measured
//! by the benches and the report on the same inputs as tridist, and judged against the same
//! oracle (distance only: `query::distance` returns no points).

use std::time::Duration;

use tridist::{Engine, Isa, Real, Triangle};

use crate::eval::{summarise, truth, Output, Query, Stats};
use crate::families::{generate, Case};
use crate::Family;

/// A precision parry has a crate for.
pub trait Peer: Real {
    /// parry's triangle shape in this precision.
    type Shape;
    /// The triangle as a parry shape.
    fn shape(t: &Triangle<Self>) -> Self::Shape;
    /// parry's distance (not squared) between two triangles.
    fn distance(a: &Self::Shape, b: &Self::Shape) -> Self;
}

/// Implements [`Peer`] for one parry crate (the two differ only in their scalar type).
macro_rules! peer {
    ($t:ty, $parry:ident) => {
        impl Peer for $t {
            type Shape = $parry::shape::Triangle;
            fn shape(t: &Triangle<$t>) -> Self::Shape {
                let v = |p: [$t; 3]| $parry::math::Vector::new(p[0], p[1], p[2]);
                $parry::shape::Triangle::new(v(t[0]), v(t[1]), v(t[2]))
            }
            fn distance(a: &Self::Shape, b: &Self::Shape) -> $t {
                let id = $parry::math::Pose::identity();
                // Triangle-triangle is always supported; NaN marks the impossible error.
                $parry::query::distance(&id, a, &id, b).map_or(<$t>::NAN, |d| d.distance)
            }
        }
    };
}
peer!(f32, parry3d);
peer!(f64, parry3d_f64);

/// Triangle pairs converted once to parry shapes.
pub struct Shapes<T: Peer> {
    a: Vec<T::Shape>,
    b: Vec<T::Shape>,
}

impl<T: Peer> Shapes<T> {
    /// Converts the pairs.
    pub fn new(a: &[Triangle<T>], b: &[Triangle<T>]) -> Self {
        Shapes { a: a.iter().map(T::shape).collect(), b: b.iter().map(T::shape).collect() }
    }

    /// Number of pairs.
    pub fn len(&self) -> usize {
        self.a.len().min(self.b.len())
    }

    /// True when there are no pairs.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// parry's distances into `out` (one per pair).
    pub fn distances(&self, out: &mut [T]) {
        for ((o, a), b) in out.iter_mut().zip(&self.a).zip(&self.b) {
            *o = T::distance(a, b);
        }
    }
}

/// Checks that parry answers the same question as tridist on these pairs (a harness error, a
/// wrong pose or an unsquared distance would disagree on most pairs): parry's distance against
/// tridist's scalar one within `1e-3 S` (S: the pair's largest coordinate magnitude) on at least
/// 90% of the pairs. Returns the largest `|d - d'| / S` and the number of pairs beyond `1e-3`.
///
/// # Errors
/// A message when the check fails.
pub fn agreement<T: Peer>(a: &[Triangle<T>], b: &[Triangle<T>]) -> Result<(f64, usize), String> {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let (mut ours, mut theirs) = (vec![T::ZERO; n], vec![T::ZERO; n]);
    let e = Engine::new(Isa::Scalar).map_err(|e| e.to_string())?;
    e.sqdist_triangle_triangle(a, b, &mut ours).map_err(|e| e.to_string())?;
    Shapes::new(a, b).distances(&mut theirs);
    compare(a, b, &ours, &theirs)
}

/// [`agreement`]'s test on given answers: `ours` squared, `theirs` not.
fn compare<T: Real>(
    a: &[Triangle<T>],
    b: &[Triangle<T>],
    ours: &[T],
    theirs: &[T],
) -> Result<(f64, usize), String> {
    let n = ours.len();
    let (mut worst, mut beyond) = (0.0f64, 0usize);
    for i in 0..n {
        let s = a[i].iter().chain(b[i].iter()).flatten().fold(0.0f64, |m, x| m.max(x.to_f64().abs()));
        let diff = (theirs[i].to_f64() - ours[i].to_f64().sqrt()).abs() / s.max(f64::MIN_POSITIVE);
        let diff = if diff.is_nan() { f64::INFINITY } else { diff };
        worst = worst.max(diff);
        beyond += usize::from(diff > 1e-3);
    }
    if beyond * 10 > n {
        return Err(format!("parry3d ({}) disagrees with tridist on {beyond} of {n} pairs", T::NAME));
    }
    Ok((worst, beyond))
}

/// Median seconds of one pass of parry's distance over the pairs (see
/// [`crate::workload::median_time`]).
pub fn time_pass<T: Peer>(shapes: &Shapes<T>, budget: Duration) -> f64 {
    let mut out = vec![T::ZERO; shapes.len()];
    crate::workload::median_time(|| shapes.distances(&mut out), budget)
}

/// parry's triangle distance judged against the oracle on `n` cases of `family`, with the
/// metrics of ACCURACY.md. Distance only: the closest-point error of the result is meaningless
/// (no points are returned) and left at 0.
pub fn judge<T: Peer>(family: Family, seed: u64, n: usize) -> Stats {
    let cases: Vec<Case<T>> = generate::<T>(family, seed, n);
    let a: Vec<_> = cases.iter().map(|c| c.a).collect();
    let b: Vec<_> = cases.iter().map(|c| c.b).collect();
    let mut d = vec![T::ZERO; cases.len()];
    Shapes::new(&a, &b).distances(&mut d);
    // The metrics take a squared distance; squaring in T adds at most half an ulp of D, far below
    // the errors measured.
    let out = Output {
        d: d.iter().map(|&x| x * x).collect(),
        p: vec![[T::ZERO; 3]; cases.len()],
        q: vec![[T::ZERO; 3]; cases.len()],
    };
    let mut st = summarise(Query::TriTri, &cases, &truth(Query::TriTri, &cases), &out).0;
    st.max_point_error = 0.0;
    st
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parry_answers_the_same_question() {
        let a = [[[0.0f64, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]];
        let b = [[[0.0f64, 0.0, 2.0], [1.0, 0.0, 2.0], [0.0, 1.0, 2.0]]];
        let mut d = [0.0];
        Shapes::new(&a, &b).distances(&mut d);
        assert_eq!(d[0], 2.0);
        let cases: Vec<Case<f64>> = generate(Family::Random, 1, 50);
        let ca: Vec<_> = cases.iter().map(|c| c.a).collect();
        let cb: Vec<_> = cases.iter().map(|c| c.b).collect();
        let (worst, beyond) = agreement(&ca, &cb).unwrap();
        assert!(worst < 1e-9 && beyond == 0, "{worst} {beyond}");
        // a harness that compared squared with unsquared distances would be caught
        let mut ours = vec![0.0; 50];
        Engine::new(Isa::Scalar).unwrap().sqdist_triangle_triangle(&ca, &cb, &mut ours).unwrap();
        let disjoint = ours.iter().filter(|&&x| x > 1e-2).count();
        assert!(disjoint > 10);
        assert!(compare(&ca, &cb, &ours, &ours).is_err());
    }

    #[test]
    fn judged_against_the_oracle() {
        let st = judge::<f64>(Family::Random, 7, 40);
        assert_eq!(st.n, 40);
        assert!(st.max_excess.is_finite() && st.nonfinite == 0);
    }
}
