//! A rigorous floating-point filter in front of the exact 15-feature minimum.
//!
//! The exact answer of [`crate::triangle_triangle`] is the first (in a fixed order) of the 15
//! feature pairs with the smallest exact distance, or an exact piercing point. Most features
//! cannot be closest, and most pairs are provably disjoint, so this module decides that in `f64`
//! with *certified* error bounds and leaves to GMP only what it cannot decide:
//!
//! 1. For every feature pair, an approximate closest pair of parameters is computed in plain
//!    `f64` (Ericson's routines; any parameters would do). The parameters are clamped so that
//!    they name points *exactly on* the features, so the exact squared distance `|W|^2` between
//!    those two points is an upper bound on the feature's distance. `|W|^2` is evaluated with a
//!    running error bound ([`R`]), so its true value is known to lie in an interval.
//! 2. The smallest of these upper bounds (`best`) bounds the global minimum `d*` from above.
//! 3. A feature is skipped only when it is certainly farther than `best`: with `w` the computed
//!    direction between its approximate closest points, every pair of its vertices `x` (first
//!    triangle's side) and `y` (second's) satisfies `w.(x - y) > 0` and
//!    `(w.(x - y))^2 > best * |w|^2`. Since the features are convex hulls of those vertices, the
//!    projection gap on `w` then shows the feature's distance exceeds `best >= d*`: it is not a
//!    minimiser, and the first minimiser in order is the same as without the filter.
//! 4. The survivors (one to six on random input) are evaluated exactly, in the reference order.
//! 5. When the minimum is positive and the projection of all six vertices on `best`'s direction
//!    certainly separates the triangles, no edge can pierce the other triangle and the exact
//!    piercing test is skipped.
//!
//! Every decision uses the certified sign of a real expression of the input floats
//! ([`R::pos`]); non-finite intermediate values (overflow at |x| > 1e150 or so) fail every
//! test, so such input simply gets less filtering. Nothing here is a tolerance: the answer is
//! bit-for-bit the reference's, which the tests check.

use crate::{keep_min, point_triangle, segment_segment, Exact, P3};

/// Unit roundoff of `f64`.
const U: f64 = f64::EPSILON / 2.0;
/// The smallest positive subnormal: bounds the absolute error of an underflowing product.
const ETA: f64 = f64::from_bits(1);

/// A real number `x` with a certified bound: `|x - v| <= e`.
///
/// Each operation adds its own rounding error (`|fl(y) - y| <= u |fl(y)| / (1 - u) + eta / 2`
/// for round to nearest, subnormals included) and the propagated error of its operands; the bound
/// itself is computed with a few more roundings of non-negative terms, covered by the factor
/// `1 + 8u` and the `4 eta`. An infinite or NaN `v` or `e` makes every test fail.
#[derive(Clone, Copy, Debug)]
pub(crate) struct R {
    v: f64,
    e: f64,
}

impl R {
    const fn exact(v: f64) -> R {
        R { v, e: 0.0 }
    }

    fn rounded(v: f64, propagated: f64) -> R {
        R { v, e: (propagated + U * v.abs()) * (1.0 + 8.0 * U) + 4.0 * ETA }
    }

    fn add(self, o: R) -> R {
        R::rounded(self.v + o.v, self.e + o.e)
    }

    fn sub(self, o: R) -> R {
        R::rounded(self.v - o.v, self.e + o.e)
    }

    fn mul(self, o: R) -> R {
        R::rounded(self.v * o.v, self.v.abs() * o.e + o.v.abs() * self.e + self.e * o.e)
    }

    /// Certainly positive. (`v > e` is evaluated exactly: no rounding.)
    fn pos(self) -> bool {
        self.v > self.e
    }
}

type F3 = [f64; 3];

fn sub_r(a: &F3, b: &F3) -> [R; 3] {
    [0, 1, 2].map(|i| R::exact(a[i]).sub(R::exact(b[i])))
}

fn dot_r(a: &[R; 3], b: &[R; 3]) -> R {
    a[0].mul(b[0]).add(a[1].mul(b[1])).add(a[2].mul(b[2]))
}

fn sub(a: &F3, b: &F3) -> F3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: &F3, b: &F3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `0` for NaN, else `x` clamped to `[0, 1]`.
fn unit(x: f64) -> f64 {
    if x > 0.0 {
        x.min(1.0)
    } else {
        0.0
    }
}

/// Approximate parameters `(s, t)` in `[0, 1]` of the closest points of segments `p1 q1` and
/// `p2 q2` (Ericson, Real-Time Collision Detection 5.1.9). Accuracy only affects how much is
/// filtered, never the answer.
fn seg_params(p1: &F3, q1: &F3, p2: &F3, q2: &F3) -> (f64, f64) {
    let (d1, d2, r) = (sub(q1, p1), sub(q2, p2), sub(p1, p2));
    let (a, e, f) = (dot(&d1, &d1), dot(&d2, &d2), dot(&d2, &r));
    if a <= 0.0 && e <= 0.0 {
        return (0.0, 0.0);
    }
    if a <= 0.0 {
        return (0.0, unit(f / e));
    }
    let c = dot(&d1, &r);
    if e <= 0.0 {
        return (unit(-c / a), 0.0);
    }
    let b = dot(&d1, &d2);
    let denom = a * e - b * b;
    let s = if denom > 0.0 { unit((b * f - c * e) / denom) } else { 0.0 };
    let t = (b * s + f) / e;
    if t < 0.0 {
        (unit(-c / a), 0.0)
    } else if t > 1.0 {
        (unit((b - c) / a), 1.0)
    } else {
        (s, unit(t))
    }
}

/// Approximate coordinates `(v, w)` of the point of triangle `abc` closest to `p`, as
/// `a + v (b - a) + w (c - a)` (Ericson 5.1.5), made exactly feasible: `v, w >= 0`,
/// `v + w <= 1` in exact arithmetic.
fn tri_params(p: &F3, a: &F3, b: &F3, c: &F3) -> (f64, f64) {
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let (d1, d2) = (dot(&ab, &ap), dot(&ac, &ap));
    let raw = 'r: {
        if d1 <= 0.0 && d2 <= 0.0 {
            break 'r (0.0, 0.0);
        }
        let bp = sub(p, b);
        let (d3, d4) = (dot(&ab, &bp), dot(&ac, &bp));
        if d3 >= 0.0 && d4 <= d3 {
            break 'r (1.0, 0.0);
        }
        let vc = d1 * d4 - d3 * d2;
        if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
            break 'r (d1 / (d1 - d3), 0.0);
        }
        let cp = sub(p, c);
        let (d5, d6) = (dot(&ab, &cp), dot(&ac, &cp));
        if d6 >= 0.0 && d5 <= d6 {
            break 'r (0.0, 1.0);
        }
        let vb = d5 * d2 - d1 * d6;
        if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
            break 'r (0.0, d2 / (d2 - d6));
        }
        let va = d3 * d6 - d5 * d4;
        if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
            let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
            break 'r (1.0 - w, w);
        }
        let denom = 1.0 / (va + vb + vc);
        (vb * denom, vc * denom)
    };
    feasible(raw.0, raw.1)
}

/// `(v, w)` clamped so that `v, w >= 0` and `v + w <= 1` hold exactly.
fn feasible(v: f64, w: f64) -> (f64, f64) {
    let v = unit(v);
    // 1 - v is exact for v = 0 and v >= 1/2 (Sterbenz); otherwise (1 - v in (1/2, 1)) one step
    // down, by bits, makes it a lower bound of the exact 1 - v (its rounding error is below half
    // an ulp).
    let room = if v == 0.0 || v >= 0.5 { 1.0 - v } else { f64::from_bits((1.0 - v).to_bits() - 1) };
    (v, unit(w).min(room))
}

/// One feature pair's candidate: the certified `|W|^2` of two points exactly on the features
/// (`W = p - q`, `p` on the first triangle's feature) and `W`'s computed direction.
struct Cand {
    w2: R,
    dir: F3,
}

fn cand(w: [R; 3]) -> Cand {
    Cand { w2: dot_r(&w, &w), dir: [w[0].v, w[1].v, w[2].v] }
}

fn seg_seg_cand(a0: &F3, a1: &F3, b0: &F3, b1: &F3) -> Cand {
    let (s, t) = seg_params(a0, a1, b0, b1);
    let (r, d1, d2) = (sub_r(a0, b0), sub_r(a1, a0), sub_r(b1, b0));
    let (s, t) = (R::exact(s), R::exact(t));
    cand([0, 1, 2].map(|i| r[i].add(s.mul(d1[i])).sub(t.mul(d2[i]))))
}

/// `W = x - q(x)`, `q(x)` on triangle `t`.
fn point_tri_w(x: &F3, t: &[F3; 3]) -> [R; 3] {
    let (v, w) = tri_params(x, &t[0], &t[1], &t[2]);
    let (xa, e0, e1) = (sub_r(x, &t[0]), sub_r(&t[1], &t[0]), sub_r(&t[2], &t[0]));
    let (v, w) = (R::exact(v), R::exact(w));
    [0, 1, 2].map(|i| xa[i].sub(v.mul(e0[i])).sub(w.mul(e1[i])))
}

/// Certainly `dist(hull(first), hull(second))^2 > bound` (`bound` >= the true minimum), shown by
/// projecting every vertex pair on `dir`.
fn beyond(dir: &F3, first: &[&F3], second: &[&F3], bound: R) -> bool {
    let d = dir.map(R::exact);
    let dd = dot_r(&d, &d);
    first.iter().all(|x| {
        second.iter().all(|y| {
            let g = dot_r(&d, &sub_r(x, y));
            g.pos() && g.mul(g).sub(bound.mul(dd)).pos()
        })
    })
}

/// Certainly `hull(first)` and `hull(second)` are disjoint: every vertex pair projects on
/// `dir` with a positive gap.
fn separated(dir: &F3, first: &[F3; 3], second: &[F3; 3]) -> bool {
    let d = dir.map(R::exact);
    first.iter().all(|x| second.iter().all(|y| dot_r(&d, &sub_r(x, y)).pos()))
}

/// The feature pairs in the reference order of `min15`.
#[derive(Clone, Copy)]
enum Feature {
    /// Edge `i` of the first triangle against edge `j` of the second.
    SegSeg(usize, usize),
    /// Vertex `k` of the first triangle against the second triangle.
    VertexFace(usize),
    /// The first triangle against vertex `k` of the second.
    FaceVertex(usize),
}

const FEATURES: [Feature; 15] = {
    use Feature::*;
    [
        SegSeg(0, 0),
        SegSeg(0, 1),
        SegSeg(0, 2),
        SegSeg(1, 0),
        SegSeg(1, 1),
        SegSeg(1, 2),
        SegSeg(2, 0),
        SegSeg(2, 1),
        SegSeg(2, 2),
        VertexFace(0),
        FaceVertex(0),
        VertexFace(1),
        FaceVertex(1),
        VertexFace(2),
        FaceVertex(2),
    ]
};

/// The filtered 15-feature minimum plus piercing: the same [`Exact`] as the reference
/// `triangle_triangle`, for triangles whose exact coordinates `s`, `t` are the floats `sf`, `tf`.
pub(crate) fn triangle_triangle(s: &[P3; 3], t: &[P3; 3], sf: &[F3; 3], tf: &[F3; 3]) -> Exact {
    let nx = |k: usize| (k + 1) % 3;
    let cands: Vec<Cand> = FEATURES
        .iter()
        .map(|f| match *f {
            Feature::SegSeg(i, j) => seg_seg_cand(&sf[i], &sf[nx(i)], &tf[j], &tf[nx(j)]),
            Feature::VertexFace(k) => cand(point_tri_w(&sf[k], tf)),
            Feature::FaceVertex(k) => cand(point_tri_w(&tf[k], sf).map(|w| R::exact(0.0).sub(w))),
        })
        .collect();
    let best = cands
        .iter()
        .min_by(|a, b| (a.w2.v + a.w2.e).total_cmp(&(b.w2.v + b.w2.e)))
        .unwrap_or_else(|| unreachable!("15 candidates"));
    let mut min: Option<Exact> = None;
    for (f, c) in FEATURES.iter().zip(&cands) {
        let (first, second): (Vec<&F3>, Vec<&F3>) = match *f {
            Feature::SegSeg(i, j) => (vec![&sf[i], &sf[nx(i)]], vec![&tf[j], &tf[nx(j)]]),
            Feature::VertexFace(k) => (vec![&sf[k]], tf.iter().collect()),
            Feature::FaceVertex(k) => (sf.iter().collect(), vec![&tf[k]]),
        };
        if !core::ptr::eq(c, best) && beyond(&c.dir, &first, &second, best.w2) {
            continue;
        }
        let exact = match *f {
            Feature::SegSeg(i, j) => {
                segment_segment(&[s[i].clone(), s[nx(i)].clone()], &[t[j].clone(), t[nx(j)].clone()])
            }
            Feature::VertexFace(k) => point_triangle(&s[k], t),
            Feature::FaceVertex(k) => point_triangle(&t[k], s).swap(),
        };
        keep_min(&mut min, exact);
    }
    let min = min.unwrap_or_else(|| unreachable!("the best candidate is always evaluated"));
    if min.d2 == 0 || separated(&best.dir, sf, tf) {
        return min;
    }
    crate::pierce_or(min, s, t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn running_error_bounds_hold() {
        // (1 + 2^-30)^2 - 1 = 2^-29 + 2^-60: the f64 result drops 2^-60, the bound covers it.
        let x = R::exact(1.0 + 2f64.powi(-30));
        let y = x.mul(x).sub(R::exact(1.0));
        let truth = 2f64.powi(-29) + 2f64.powi(-60);
        assert!((y.v - truth).abs() <= y.e && y.e < 1e-15);
        // an underflowing product keeps a positive bound
        let tiny = R::exact(1e-200).mul(R::exact(1e-200));
        assert_eq!(tiny.v, 0.0);
        assert!(tiny.e > 0.0 && !tiny.pos());
        // overflow decides nothing
        let huge = R::exact(1e300).mul(R::exact(1e300));
        assert!(!huge.pos() && !R::exact(0.0).sub(huge).pos());
        let nan = huge.sub(huge);
        assert!(!nan.pos());
    }

    #[test]
    fn feasible_parameters_are_exactly_feasible() {
        let q = |x: f64| rug::Rational::from_f64(x).unwrap();
        let vs = [0.0, 1e-300, 1e-17, 0.1, 0.3, 0.49999999999999994, 0.5, 0.7, 1.0, 1.5, -0.2, f64::NAN];
        for v in vs {
            for w in vs.iter().copied().chain([1.0 - v, 1.0, 0.9, 1.0 - v + 1e-16]) {
                let (a, b) = feasible(v, w);
                assert!(a >= 0.0 && b >= 0.0 && q(a) + q(b) <= 1, "v = {v}, w = {w}: {a} {b}");
                // nothing is lost when the input is already feasible
                if v >= 0.0 && w >= 0.0 && q(v) + q(w) <= 1 && (v == 0.0 || v >= 0.5) {
                    assert_eq!((a, b), (v, w));
                }
            }
        }
    }
}
