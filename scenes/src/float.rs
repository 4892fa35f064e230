//! The precisions as the harness sees them: `tridist::Real` plus bit patterns and a name
//! (ulp steps, failure messages that print bits).

use tridist::{Precision, Real};

/// `f32` or `f64`, with bit access.
pub trait Float: Real {
    /// "f32" or "f64".
    const NAME: &'static str;
    /// Raw bits, widened.
    fn to_bits_u64(self) -> u64;
    /// From raw bits (the low 32 for f32).
    fn from_bits_u64(b: u64) -> Self;
}

impl Float for f32 {
    const NAME: &'static str = "f32";
    fn to_bits_u64(self) -> u64 {
        self.to_bits() as u64
    }
    fn from_bits_u64(b: u64) -> Self {
        f32::from_bits(b as u32)
    }
}

impl Float for f64 {
    const NAME: &'static str = "f64";
    fn to_bits_u64(self) -> u64 {
        self.to_bits()
    }
    fn from_bits_u64(b: u64) -> Self {
        f64::from_bits(b)
    }
}

/// The oracle's view of a precision.
pub fn metrics_precision(p: Precision) -> tridist_oracle::metrics::Precision {
    match p {
        Precision::F32 => tridist_oracle::metrics::F32,
        Precision::F64 => tridist_oracle::metrics::F64,
    }
}
