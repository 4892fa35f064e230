//! The bound table: allowed excess E, closest-point error and classification errors per
//! (query, variant, precision, family), each row with a reason. Printed beside the measured
//! figures by `tridist report` (reports/ACCURACY.md) and enforced by `scenes/tests`.
//!
//! How the numbers were set: `cargo run --release -p tridist-scenes --example measure 1000`
//! (1000 cases per family, every variant and precision), then the target below wherever the
//! measurement fits it with margin, and a measured override with its reason where not.
//! Measured maxima (seed 0x7121d157, 300-1000 cases): excess E <= 3.95 and closest-point error
//! <= 3.9 on every query, variant, precision and family; zero contact misses, false zeros beyond
//! 8 u S, and non-finite outputs. History: closest points of contacts reached 131 u S on thin
//! triangles until point-triangle projected along an accurate normal (then the table needed an
//! override; it no longer does).

use crate::eval::{Query, Variant};
use crate::families::Family;

/// One row of the table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bound {
    /// Largest allowed excess E (over the correctly rounded answer).
    pub max_excess: f64,
    /// Largest allowed closest-point error (offset from the primitive, or `|p - q|` against
    /// the exact distance), scaled like E.
    pub max_point_error: f64,
    /// Allowed contact misses + false zeros beyond `c u S` + non-finite outputs.
    pub max_misclassified: usize,
    /// Why this bound.
    pub reason: &'static str,
}

/// The target of ACCURACY.md: a stable kernel keeps E below a small constant on every family.
pub const TARGET: f64 = 8.0;

const DEFAULT: Bound = Bound {
    max_excess: TARGET,
    max_point_error: TARGET,
    max_misclassified: 0,
    reason: "target E <= 8 (ACCURACY.md); measured max 3.95 over all rows at n = 1000",
};

/// The declared bound for a combination. Every variant and precision shares a row today: the
/// measured figures differ between them (FMA changes rounding) but all meet the same bounds.
pub fn bound(query: Query, variant: Variant, precision: &str, family: Family) -> Bound {
    let _ = variant;
    match (query, family) {
        (Query::Intersect, Family::Touching | Family::NearMiss | Family::Degenerate) => Bound {
            max_misclassified: usize::MAX,
            reason: "overlap verdicts on pairs that touch exactly (or miss by a few ulps) are within \
                     rounding of the input: counted and published, not bounded. The fuzzer found \
                     f32 verdicts of 'disjoint' for a vertex rounded onto a face at 1e20, and f64 ones for \
                     two nearly degenerate triangles whose segments cross exactly, and (avx2fma) \
                     'disjoint' for a segment whose endpoint lies exactly on a needle's edge. The \
                     fuzz harness judges every pair that only touches (oracle::touching_only) by \
                     this row, whatever construction built it.",
            ..DEFAULT
        },
        (Query::Penalty, _) => {
            // No useful worst case: only that the returned points are feasible, so the error is
            // below the pair's extent (E <= 8 / u means an error of at most 8 S).
            let u = if precision == "f32" { f32::EPSILON as f64 / 2.0 } else { f64::EPSILON / 2.0 };
            Bound {
                max_excess: 8.0 / u,
                max_point_error: 8.0 / u,
                max_misclassified: usize::MAX,
                reason: "penalty method (default options) is an approximation with no useful \
                         worst-case bound: measured median E < 1 on every family, but max E of \
                         O(1/u) (errors of order S) where 32 regularised Newton steps stall or \
                         settle on a wrong active set, and contact misses on touching and \
                         intersecting pairs (counted and published). The bound only asserts \
                         feasible points (error < 8 S) and, as in every row, finite results.",
            }
        }
        _ => DEFAULT,
    }
}

/// Does a measured row meet its bound? Non-finite output for finite input never does. Written
/// so that NaN figures fail.
pub fn meets(s: &crate::eval::Stats, b: &Bound) -> bool {
    let misclassified = s.contact_misses + s.false_zeros + s.nonfinite;
    s.max_excess <= b.max_excess
        && s.max_point_error <= b.max_point_error
        && misclassified <= b.max_misclassified
        && s.nonfinite == 0
}

/// Runs `query` on every available variant over `cases` (whose exact answers are `truth`) and
/// judges each against its row of the table; returns a reproducible description of every
/// violation (empty when all variants meet their bounds).
///
/// An intersection verdict on a pair that only touches (`tridist_oracle::touching_only`: exact
/// contact that shrinking both triangles by 2^-8 removes) is within rounding of the input, so
/// such cases are judged by the touching row whatever family generated them (the extensive run
/// found them among near-parallel pairs, the fuzzer among "random" constructions).
pub fn violations<T: tridist::Real>(
    query: Query,
    family: Family,
    cases: &[crate::Case<T>],
    truth: &[crate::eval::Truth],
) -> Vec<String> {
    if query == Query::Intersect && family != Family::Touching {
        let touch: Vec<bool> = cases.iter().zip(truth).map(|(c, t)| t.d2 == 0 && touching(c)).collect();
        if touch.iter().any(|&x| x) {
            let pick = |want: bool| -> (Vec<crate::Case<T>>, Vec<crate::eval::Truth>) {
                let idx = (0..cases.len()).filter(|&i| touch[i] == want);
                idx.map(|i| (cases[i].clone(), truth[i].clone())).unzip()
            };
            let (tc, tt) = pick(true);
            let (oc, ot) = pick(false);
            let mut out = violations(query, Family::Touching, &tc, &tt);
            if !oc.is_empty() {
                out.extend(violations(query, family, &oc, &ot));
            }
            return out;
        }
    }
    let mut out = Vec::new();
    for v in Variant::ALL {
        let Ok(o) = crate::eval::run(query, v, cases) else { continue };
        let (st, js) = crate::eval::summarise(query, cases, truth, &o);
        let b = bound(query, v, T::NAME, family);
        if !meets(&st, &b) {
            let w = st.worst.unwrap_or(0);
            out.push(format!(
                "{} {} {} {}: {st:?} exceeds {b:?}\n{}",
                query.name(),
                v.name(),
                T::NAME,
                family.name(),
                crate::eval::describe(query, &cases[w], &truth[w], &o, w, &js[w])
            ));
        }
    }
    out
}

fn touching<T: tridist::Real>(c: &crate::Case<T>) -> bool {
    let ex = |t: &tridist::Triangle<T>| tridist_oracle::exact_points(&t.map(|p| p.map(|x| x.to_f64())));
    match (ex(&c.a), ex(&c.b)) {
        (Ok(a), Ok(b)) => tridist_oracle::touching_only(&a, &b),
        _ => false,
    }
}
