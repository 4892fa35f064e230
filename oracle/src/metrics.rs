//! The error metrics of `ACCURACY.md`, shared by tests, fuzz targets and reports.
//!
//! * [`scaled_error`]: `E = |sqrt(D^) - d*| / (u*S)`, the primary figure;
//! * [`floor_error`]: the `E` of the correctly rounded exact answer (what even a perfect kernel
//!   returning a rounded squared distance incurs); [`excess`] is `max(0, E - floor)`;
//! * [`ulp_error`]: ULP error of the squared distance, where `D* >= (2^10 u S)^2`;
//! * [`contact_miss`] / [`false_zero`]: contact classification;
//! * [`point_offset`] / [`gap_error`]: closest-point validity.

use rug::Rational;

use crate::{round, P3};

/// A working precision as the metrics see it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Precision {
    /// Unit roundoff (2^-24 or 2^-53).
    pub u: f64,
    /// Smallest positive normal.
    pub min_normal: f64,
    /// "f32" or "f64".
    pub name: &'static str,
}

/// f32.
pub const F32: Precision =
    Precision { u: 5.960464477539063e-8, min_normal: f32::MIN_POSITIVE as f64, name: "f32" };
/// f64.
pub const F64: Precision =
    Precision { u: 1.1102230246251565e-16, min_normal: f64::MIN_POSITIVE, name: "f64" };

impl Precision {
    /// Correctly rounds an exact value in this precision (returned as f64).
    pub fn round(&self, q: &Rational) -> f64 {
        if self.name == "f32" {
            round::to_f32(q) as f64
        } else {
            round::to_f64(q)
        }
    }
    /// Unit in the last place of a positive exact value in this precision.
    pub fn ulp(&self, q: &Rational) -> f64 {
        let (p, emin) = if self.name == "f32" { (24, -126) } else { (53, -1022) };
        let x = q.to_f64().abs();
        let e = if x == 0.0 { emin } else { (x.log2().floor() as i32).max(emin) };
        2f64.powi(e - p + 1)
    }
}

/// `s^2` exactly (1 for a zero or non-finite `s`).
fn square(s: f64) -> Rational {
    let sr = Rational::from_f64(s).filter(|x| *x != 0).unwrap_or_else(|| Rational::from(1));
    Rational::from(&sr * &sr)
}

/// The magnitude `S`: the largest absolute coordinate, at least the smallest positive normal.
pub fn magnitude(coords: impl IntoIterator<Item = f64>, prec: Precision) -> f64 {
    coords.into_iter().fold(prec.min_normal, |m, x| m.max(x.abs()))
}

/// `E = |sqrt(d2_hat) - sqrt(exact)| / (u*S)`, computed as
/// `|d2_hat - exact| / ((sqrt(d2_hat) + sqrt(exact)) * u*S)` with the numerator exact.
/// NaN for NaN input, +inf for an infinite `d2_hat`, 0 when both are 0.
pub fn scaled_error(d2_hat: f64, exact: &Rational, s: f64, prec: Precision) -> f64 {
    if d2_hat.is_nan() {
        return f64::NAN;
    }
    if d2_hat.is_infinite() || d2_hat < 0.0 {
        return f64::INFINITY;
    }
    let dh = Rational::from_f64(d2_hat).unwrap_or_default();
    let s2 = square(s);
    let num = Rational::from(&dh - exact).abs() / &s2;
    let a = (dh / &s2).to_f64().sqrt();
    let b = Rational::from(exact / &s2).to_f64().sqrt();
    let den = (a + b) * prec.u;
    if den == 0.0 {
        return 0.0;
    }
    num.to_f64() / den
}

/// `E` of the correctly rounded exact answer.
pub fn floor_error(exact: &Rational, s: f64, prec: Precision) -> f64 {
    let r = prec.round(exact);
    if r.is_infinite() {
        return 0.0;
    }
    scaled_error(r, exact, s, prec)
}

/// The largest finite value of the precision.
fn largest(prec: Precision) -> f64 {
    if prec.name == "f32" {
        f32::MAX as f64
    } else {
        f64::MAX
    }
}

/// Is `+inf` a documented answer: does some distance within `reach * u * S` of the exact one
/// square beyond the precision's largest finite value? That covers `D*` itself above it (even
/// when it rounds down to it) and answers within the error bound `reach` (the E target) whose
/// square overflows. The criterion is evaluated in `f64` (its edge is not exactness-critical).
pub fn overflow_allowed(exact: &Rational, s: f64, prec: Precision, reach: f64) -> bool {
    if prec.round(exact).is_infinite() {
        return true;
    }
    let d = exact.to_f64().sqrt() + reach * prec.u * s;
    d * d > largest(prec)
}

/// The reach of [`overflow_allowed`] that [`excess`] uses: the E target of ACCURACY.md.
pub const OVERFLOW_REACH: f64 = 8.0;

/// `max(0, E - floor E)`: the error the kernel adds beyond rounding its answer. When the exact
/// squared distance rounds to `+inf` in the precision, `+inf` is the right answer (excess 0) and
/// a finite answer is judged by its own error (as everywhere: an answer within the E target may
/// square just below the largest finite value where the exact square lies just above it); `+inf`
/// is also excess 0 where an answer within the E target would overflow ([`overflow_allowed`]).
pub fn excess(d2_hat: f64, exact: &Rational, s: f64, prec: Precision) -> f64 {
    excess_within(d2_hat, exact, s, prec, OVERFLOW_REACH)
}

/// [`excess`] for a method whose error bound is `reach` (in units of `u S`) instead of the E
/// target: `+inf` is excess 0 where an answer within `reach` would overflow (an approximation
/// such as the penalty method, bounded by `8 S`, uses `reach = 8 / u`).
pub fn excess_within(d2_hat: f64, exact: &Rational, s: f64, prec: Precision, reach: f64) -> f64 {
    let r = prec.round(exact);
    if r.is_infinite() {
        // (the correctly rounded answer is +inf: its floor error is 0)
        return if d2_hat == f64::INFINITY { 0.0 } else { scaled_error(d2_hat, exact, s, prec) };
    }
    if d2_hat == f64::INFINITY && overflow_allowed(exact, s, prec, reach) {
        return 0.0;
    }
    let e = scaled_error(d2_hat, exact, s, prec);
    (e - floor_error(exact, s, prec)).max(0.0)
}

/// ULP error of the squared distance, only where `exact >= (2^10 u S)^2` and the exact value is
/// representable (otherwise `None`: meaningless near contact).
pub fn ulp_error(d2_hat: f64, exact: &Rational, s: f64, prec: Precision) -> Option<f64> {
    if !s.is_finite() {
        return None;
    }
    let thr = us_squared(1024.0, s, prec);
    if *exact < thr || prec.round(exact).is_infinite() || !d2_hat.is_finite() {
        return None;
    }
    let dh = Rational::from_f64(d2_hat)?;
    Some(Rational::from(&dh - exact).abs().to_f64() / prec.ulp(exact))
}

/// A contact miss: the exact distance is 0 but the kernel reports more than `c*u*S` (compared
/// exactly: the squared answer against `(c u S)^2`).
pub fn contact_miss(d2_hat: f64, exact: &Rational, s: f64, prec: Precision, c: f64) -> bool {
    if *exact != 0 {
        return false;
    }
    match Rational::from_f64(d2_hat) {
        None => d2_hat.is_nan() || (d2_hat == f64::INFINITY && s.is_finite()),
        Some(d) => s.is_finite() && d > us_squared(c, s, prec),
    }
}

/// A strict false zero: the exact distance is positive (and does not round to 0), the kernel
/// says exactly 0.
pub fn false_zero_strict(d2_hat: f64, exact: &Rational, prec: Precision) -> bool {
    *exact > 0 && d2_hat == 0.0 && prec.round(exact) != 0.0
}

/// A false zero beyond the contact tolerance: the exact distance exceeds `c*u*S` and the kernel
/// says 0. (Pairs a few ulps apart may legitimately be reported as touching: the decision is
/// within rounding of the input; the strict count is reported separately.) A squared distance
/// that rounds to 0 in the precision (underflow) is not a false zero.
pub fn false_zero(d2_hat: f64, exact: &Rational, s: f64, prec: Precision, c: f64) -> bool {
    d2_hat == 0.0 && *exact > us_squared(c, s, prec) && prec.round(exact) != 0.0
}

/// `c u S` exactly (0 for a non-finite `c` or `S`). The thresholds of these metrics are
/// multiples of `u S`, which in `f64` arithmetic underflows where `S` is near the smallest
/// normal (`2^-53 * 2^-1022` is below the smallest subnormal; its square, far below): an
/// all-subnormal f64 input (`S` is then the smallest normal) had no allowance at all, and an
/// intersection verdict `2 u S` from touching, within the bound table's allowance, was judged
/// wrong (`fuzz/regressions/intersect/subnormal-point-2uS-from-segment`).
pub fn c_us(c: f64, s: f64, prec: Precision) -> Rational {
    let r = |x: f64| Rational::from_f64(x).unwrap_or_default();
    r(c) * r(prec.u) * r(s)
}

/// `(c u S)^2` exactly ([`c_us`]).
fn us_squared(c: f64, s: f64, prec: Precision) -> Rational {
    let t = c_us(c, s, prec);
    Rational::from(&t * &t)
}

/// How far a returned point lies from its primitive (1, 2 or 3 points), scaled by `u*S`.
/// `+inf` for a non-finite point.
pub fn point_offset(p: [f64; 3], prim: &[P3], s: f64, prec: Precision) -> f64 {
    let Some(x) = p.iter().map(|&c| Rational::from_f64(c)).collect::<Option<Vec<_>>>() else {
        return f64::INFINITY;
    };
    let x: P3 = [x[0].clone(), x[1].clone(), x[2].clone()];
    let d2 = match prim {
        [a] => crate::dot(&crate::sub(&x, a), &crate::sub(&x, a)),
        [a, b] => {
            let q = crate::closest_point_segment(&x, a, b);
            crate::dot(&crate::sub(&x, &q), &crate::sub(&x, &q))
        }
        [a, b, c] => crate::point_triangle(&x, &[a.clone(), b.clone(), c.clone()]).d2,
        _ => return f64::NAN,
    };
    scaled_error(0.0, &d2, s, prec)
}

/// `| |p - q| - d* | / (u*S)`: do the returned points realise the exact distance?
pub fn gap_error(p: [f64; 3], q: [f64; 3], exact: &Rational, s: f64, prec: Precision) -> f64 {
    let conv = |v: [f64; 3]| -> Option<P3> {
        Some([Rational::from_f64(v[0])?, Rational::from_f64(v[1])?, Rational::from_f64(v[2])?])
    };
    let (Some(a), Some(b)) = (conv(p), conv(q)) else { return f64::INFINITY };
    let d = crate::sub(&a, &b);
    let pq2 = crate::dot(&d, &d);
    // E between sqrt(pq2) and sqrt(exact), both exact: |pq2 - exact| / (sqrt + sqrt).
    let s2 = square(s);
    let num = Rational::from(&pq2 - exact).abs() / &s2;
    let den = ((pq2 / &s2).to_f64().sqrt() + Rational::from(exact / &s2).to_f64().sqrt()) * prec.u;
    if den == 0.0 {
        0.0
    } else {
        num.to_f64() / den
    }
}
