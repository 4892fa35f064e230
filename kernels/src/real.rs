//! The two working precisions, `f32` and `f64`, behind one sealed trait.

use core::fmt::{Debug, Display};
use core::ops::{Add, Div, Mul, Neg, Sub};

/// The seal, which also carries the batch plumbing: `Sealed` lives in a private module, so no
/// other crate can implement or name it, and its method takes a [`crate::driver::Job`], a type
/// in a private module that no other crate can construct. Safe code outside this crate cannot
/// reach the `#[target_feature]` entry points.
pub(crate) mod sealed {
    pub(crate) trait Sealed: Sized {
        /// Runs a batch job on an ISA variant (checks availability itself).
        fn run_job(isa: crate::Isa, job: &mut crate::driver::Job<'_, Self>);
    }
}

/// A working precision: `f32` or `f64`. Sealed; every query is generic over it.
// The crate-private supertrait is the seal (and keeps the plumbing unnameable from outside).
#[allow(private_bounds)]
pub trait Real:
    sealed::Sealed
    + Copy
    + Debug
    + Display
    + core::fmt::LowerExp
    + core::str::FromStr
    + Default
    + PartialOrd
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// Unit roundoff `u` (2^-24 for f32, 2^-53 for f64).
    const UNIT_ROUNDOFF: Self;
    /// Smallest positive normal number.
    const MIN_POSITIVE: Self;
    /// Largest finite number.
    const MAX: Self;
    /// Positive infinity.
    const INFINITY: Self;
    /// A quiet NaN.
    const NAN: Self;
    /// Zero.
    const ZERO: Self;
    /// One.
    const ONE: Self;
    /// A mask that keeps only the exponent bits (used for power-of-two scaling).
    const EXP_MASK_BITS: u64;
    /// Name used in reports: "f32" or "f64".
    const NAME: &'static str;
    /// Conversion from f64 (rounding).
    fn from_f64(x: f64) -> Self;
    /// Conversion to f64 (exact).
    fn to_f64(self) -> f64;
    /// Is the value finite?
    fn is_finite(self) -> bool;
    /// Raw bits, widened to u64.
    fn to_bits_u64(self) -> u64;
    /// From raw bits (the low 32 bits for f32).
    fn from_bits_u64(b: u64) -> Self;
    /// Square root.
    fn sqrt(self) -> Self;
}

macro_rules! impl_real {
    ($t:ty, $bits:ty, $mask:expr, $name:expr, $run:ident) => {
        impl Real for $t {
            const UNIT_ROUNDOFF: Self = <$t>::EPSILON / 2.0;
            const MIN_POSITIVE: Self = <$t>::MIN_POSITIVE;
            const MAX: Self = <$t>::MAX;
            const INFINITY: Self = <$t>::INFINITY;
            const NAN: Self = <$t>::NAN;
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            const EXP_MASK_BITS: u64 = $mask;
            const NAME: &'static str = $name;
            #[inline(always)]
            fn from_f64(x: f64) -> Self {
                x as $t
            }
            #[inline(always)]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline(always)]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
            #[inline(always)]
            fn to_bits_u64(self) -> u64 {
                self.to_bits() as u64
            }
            #[inline(always)]
            fn from_bits_u64(b: u64) -> Self {
                <$t>::from_bits(b as $bits)
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
        }
        impl sealed::Sealed for $t {
            fn run_job(isa: crate::Isa, job: &mut crate::driver::Job<'_, Self>) {
                crate::dispatch::$run(isa, job)
            }
        }
    };
}
impl_real!(f32, u32, 0x7f80_0000, "f32", run_f32);
impl_real!(f64, u64, 0x7ff0_0000_0000_0000, "f64", run_f64);
