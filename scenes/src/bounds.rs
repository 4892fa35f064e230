//! The bound table: allowed excess E (maximum, 99th percentile, median), closest-point error,
//! classification errors and the verdict allowance per (query, variant, precision, family),
//! each row with a reason. Printed beside the measured figures by `tridist report`
//! (reports/ACCURACY.md) and enforced by `scenes/tests`, the fuzz targets and the regression
//! replays.
//!
//! Every row can fail: certified intervals must contain the exact distance (0 misses), verdicts
//! and margin decisions may be wrong only within `allow * u * S` of a change (decided exactly
//! by the oracle: the exact distance, or the penetration depth), and the E rows sit close above
//! what is measured (libm-test style), so a regression from 1.6 to 7 is caught.

use crate::eval::Variant;
use crate::families::Family;
use crate::float::Float;
use tridist::Query;

/// One row of the table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bound {
    /// Largest allowed excess E (over the correctly rounded answer).
    pub max_excess: f64,
    /// Largest allowed 99th percentile of E.
    pub p99: f64,
    /// Largest allowed median of E.
    pub median: f64,
    /// Largest allowed closest-point error (offset from the primitive, or `|p - q|` against
    /// the exact distance), scaled like E.
    pub max_point_error: f64,
    /// Allowed contact misses + false zeros beyond `c u S` + non-finite outputs.
    pub max_misclassified: usize,
    /// Verdict and margin-decision allowance, in `u S`: a wrong side within this of a change of
    /// verdict is not counted.
    pub allow: f64,
    /// Why this bound.
    pub reason: &'static str,
}

/// The target of ACCURACY.md: a stable kernel keeps E below a small constant on every family.
pub const TARGET: f64 = 8.0;

/// The default tolerance of the certified pipeline (`tridist::Tolerance::DEFAULT`), plus one
/// unit for the rounding of the decision itself: a pair within the tolerance of contact may
/// be reported intersecting (documented), never one farther; "disjoint" is always proven.
pub const VERDICT_ALLOW: f64 = 33.0;

const DEFAULT: Bound = Bound {
    max_excess: TARGET,
    p99: TARGET,
    median: TARGET,
    max_point_error: TARGET,
    max_misclassified: 0,
    allow: VERDICT_ALLOW,
    reason: "target E <= 8 (ACCURACY.md)",
};

/// The declared bound for a combination.
pub fn bound(query: Query, variant: Variant, precision: &str, family: Family) -> Bound {
    let _ = (variant, family);
    match query {
        Query::Penalty => {
            // Feasible points: error below 8 S at worst.
            let u = if precision == "f32" { f32::EPSILON as f64 / 2.0 } else { f64::EPSILON / 2.0 };
            Bound {
                max_excess: 8.0 / u,
                p99: 8.0 / u,
                median: TARGET,
                max_point_error: 8.0 / u,
                max_misclassified: usize::MAX,
                reason: "penalty method (default options): an approximation",
                ..DEFAULT
            }
        }
        _ => DEFAULT,
    }
}

/// Rows of fewer cases are judged by their maxima only.
pub const MIN_FOR_PERCENTILES: usize = 100;

/// Does a measured row meet its bound? Non-finite output for finite input, an interval that
/// misses the exact distance, or a misjudged verdict never does. Written so that NaN figures
/// fail.
pub fn meets(s: &crate::eval::Stats, b: &Bound) -> bool {
    let misclassified = s.contact_misses + s.false_zeros + s.nonfinite;
    // Percentiles are meaningful over a family sample, not over a single fuzz input.
    let percentiles = s.n < MIN_FOR_PERCENTILES || (s.p99 <= b.p99 && s.median <= b.median);
    s.max_excess <= b.max_excess
        && percentiles
        && s.max_point_error <= b.max_point_error
        && misclassified <= b.max_misclassified
        && s.nonfinite == 0
        && s.interval_misses == 0
        && s.misjudged == 0
}

/// Runs `query` on every available variant over `cases` (whose exact answers are `truth`) and
/// judges each against its row of the table; returns a reproducible description of every
/// violation (empty when all variants meet their bounds). Within-margin uses
/// [`crate::eval::margins`].
pub fn violations<T: Float>(
    query: Query,
    family: Family,
    cases: &[crate::Case<T>],
    truth: &[crate::eval::Truth],
) -> Vec<String> {
    let ms = crate::eval::margins(cases, truth);
    let mut out = Vec::new();
    for v in Variant::ALL {
        let Ok(o) = crate::eval::run(query, v, cases, Some(&ms)) else { continue };
        let b = bound(query, v, T::NAME, family);
        let (st, js) = crate::eval::summarise(query, cases, truth, &o, b.allow, Some(&ms));
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
