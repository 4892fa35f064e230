//! Correctly rounded conversion of exact rationals to `f32` and `f64` (round to nearest, ties to
//! even, subnormals and overflow to infinity included). rug's own `Rational::to_f64` rounds
//! toward zero, which is not what the metrics need.

use rug::{Integer, Rational};

/// An IEEE binary format: precision in bits, minimum and maximum normal exponent.
#[derive(Clone, Copy, Debug)]
struct Format {
    p: i64,
    emin: i64,
    emax: i64,
}

const F32: Format = Format { p: 24, emin: -126, emax: 127 };
const F64: Format = Format { p: 53, emin: -1022, emax: 1023 };

/// `2^k` as an f64, exactly (k in -1074..=1023).
fn pow2(k: i64) -> f64 {
    debug_assert!((-1074..=1023).contains(&k));
    if k >= -1022 {
        f64::from_bits(((k + 1023) as u64) << 52)
    } else {
        f64::from_bits(1u64 << (k + 1074))
    }
}

/// Rounds `|q|` in `fmt`, returning the value as an exact f64 (infinite on overflow).
fn round_abs(a: &Rational, fmt: Format) -> f64 {
    if *a == 0 {
        return 0.0;
    }
    // 2^e <= a < 2^(e+1)
    let mut e = a.numer().significant_bits() as i64 - a.denom().significant_bits() as i64;
    let two_e = pow2_rational(e);
    if *a < two_e {
        e -= 1;
    }
    if e > fmt.emax {
        return f64::INFINITY;
    }
    let qe = e.max(fmt.emin) - (fmt.p - 1);
    let scaled = a * pow2_rational(-qe);
    let (frac, mut mi) = scaled.fract_floor(Integer::new());
    let half = Rational::from((1, 2));
    if frac > half || (frac == half && mi.is_odd()) {
        mi += 1;
    }
    // mi <= 2^p; the carry case mi == 2^p may push past emax.
    if qe + mi.significant_bits() as i64 - 1 > fmt.emax {
        return f64::INFINITY;
    }
    let m = mi.to_f64(); // exact: mi <= 2^53
    m * pow2(qe)
}

fn pow2_rational(k: i64) -> Rational {
    let one = Rational::from(1);
    if k >= 0 {
        one << (k as u32)
    } else {
        one >> ((-k) as u32)
    }
}

fn round_in(q: &Rational, fmt: Format) -> f64 {
    let a = Rational::from(q.abs_ref());
    let r = round_abs(&a, fmt);
    if *q < 0 {
        -r
    } else {
        r
    }
}

/// `q` correctly rounded to f64.
pub fn to_f64(q: &Rational) -> f64 {
    round_in(q, F64)
}

/// `q` correctly rounded to f32.
pub fn to_f32(q: &Rational) -> f32 {
    // The f64 holds an exactly representable f32 value (or infinity): the cast is exact.
    round_in(q, F32) as f32
}

/// `sqrt(a)` rounded in `fmt` (to nearest, ties to even) for `a >= 0`, as an exact f64
/// (infinite on overflow). Exact in integers: with the quantum `2^qe` of the result's binade,
/// `m = floor(sqrt(a) / 2^qe) = isqrt(floor(a / 4^qe))`, and `sqrt(a) / 2^qe` lies above
/// `m + 1/2` exactly when `a / 4^qe > m^2 + m + 1/4` (a tie when equal).
fn sqrt_round_abs(a: &Rational, fmt: Format) -> f64 {
    if *a == 0 {
        return 0.0;
    }
    // 2^e <= a < 2^(e+1), so 2^(e div 2) <= sqrt(a) < 2^(e div 2 + 1) (floor division)
    let mut e = a.numer().significant_bits() as i64 - a.denom().significant_bits() as i64;
    if *a < pow2_rational(e) {
        e -= 1;
    }
    let se = e.div_euclid(2);
    if se > fmt.emax {
        return f64::INFINITY;
    }
    let qe = se.max(fmt.emin) - (fmt.p - 1);
    let scaled = a * pow2_rational(-2 * qe);
    let (frac, floor) = scaled.fract_floor(Integer::new());
    let mut mi = floor.clone().sqrt();
    // sqrt(scaled) - mi against 1/2: scaled against mi^2 + mi + 1/4 (frac is its fraction)
    let low = Integer::from(&mi * &mi) + &mi;
    let quarter = Rational::from((1, 4));
    let above = floor > low || (floor == low && frac > quarter);
    let tie = floor == low && frac == quarter;
    if above || (tie && mi.is_odd()) {
        mi += 1;
    }
    if qe + mi.significant_bits() as i64 - 1 > fmt.emax {
        return f64::INFINITY;
    }
    mi.to_f64() * pow2(qe)
}

/// `sqrt(q)` correctly rounded to f64 (to nearest, ties to even; `None` for negative `q`).
pub fn sqrt_to_f64(q: &Rational) -> Option<f64> {
    (*q >= 0).then(|| sqrt_round_abs(q, F64))
}

/// `sqrt(q)` correctly rounded to f32 (to nearest, ties to even; `None` for negative `q`).
pub fn sqrt_to_f32(q: &Rational) -> Option<f32> {
    // The f64 holds an exactly representable f32 value (or infinity): the cast is exact.
    (*q >= 0).then(|| sqrt_round_abs(q, F32) as f32)
}
