//! The two working precisions, `f32` and `f64`, behind one sealed trait.

use core::fmt::{Debug, Display};
use core::ops::{Add, Div, Mul, Neg, Sub};

/// A working precision, as a value (reports, the CLI, error messages).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Precision {
    /// IEEE binary32.
    F32,
    /// IEEE binary64.
    F64,
}

impl Precision {
    /// Both precisions.
    pub const ALL: [Precision; 2] = [Precision::F32, Precision::F64];

    /// `"f32"` or `"f64"`.
    pub fn name(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F64 => "f64",
        }
    }

    /// Parses [`Precision::name`].
    pub fn parse(s: &str) -> Option<Precision> {
        Precision::ALL.into_iter().find(|p| p.name() == s)
    }

    /// The unit roundoff `u`: 2^-24 or 2^-53.
    pub fn unit_roundoff(self) -> f64 {
        match self {
            Precision::F32 => f32::EPSILON as f64 / 2.0,
            Precision::F64 => f64::EPSILON / 2.0,
        }
    }
}

impl Display for Precision {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// The seal. It lives in a crate-private module, so no other crate can implement or name it;
/// it also carries what the kernels need of a precision and users do not (bit patterns, and
/// the type witness [`Sealed::by_precision`] through which generic code reaches the entry
/// points of its precision).
pub(crate) mod sealed {
    /// A family of types, one for each precision (`Of<f32>`, `Of<f64>`): what a generic value
    /// is turned into by [`Sealed::by_precision`].
    pub(crate) trait Family {
        type Of<T: 'static>;
    }

    /// A value of a [`Family`] in its concrete precision.
    pub(crate) enum ByPrecision<F: Family> {
        F32(F::Of<f32>),
        F64(F::Of<f64>),
    }

    pub(crate) trait Sealed: Sized + Copy + 'static {
        /// Keeps only the exponent bits (power-of-two scaling).
        const EXP_MASK: u64;
        /// Smallest positive subnormal.
        const TINY: Self;
        /// Raw bits, widened.
        fn bits(self) -> u64;
        /// From raw bits (the low 32 for f32).
        fn from_bits64(b: u64) -> Self;
        /// This thread's spare column buffer of the batch driver's packing
        /// ([`crate::drv::Packed`]), kept from batch to batch so that a batch does not
        /// allocate and clear it.
        fn pack_spare() -> &'static std::thread::LocalKey<std::cell::RefCell<Vec<Self>>>;
        /// `x` as the value of its concrete precision: a type witness, with no conversion and
        /// no cost (the match on it is resolved when the caller is instantiated). The dispatch
        /// (`crate::arch::dispatch`) takes a generic job to its precision's entry points with
        /// it, so this module names no other of the crate.
        fn by_precision<F: Family>(x: F::Of<Self>) -> ByPrecision<F>;
        /// The next value toward -inf (toward +inf when `up`); identity on inf and NaN.
        fn step(self, up: bool) -> Self {
            let b = self.bits();
            let neg = b >> (Self::WIDTH - 1) & 1 == 1;
            let zero = b & !(1u64 << (Self::WIDTH - 1)) == 0;
            let nonfinite = b & Self::EXP_MASK == Self::EXP_MASK;
            if nonfinite {
                return self;
            }
            if zero {
                let tiny = Self::TINY.bits();
                return Self::from_bits64(if up { tiny } else { tiny | 1u64 << (Self::WIDTH - 1) });
            }
            Self::from_bits64(if up != neg { b + 1 } else { b - 1 })
        }
        /// Bits in the type.
        const WIDTH: u32;
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
    /// Which precision this is.
    const PRECISION: Precision;
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
    /// Conversion from f64 (rounding to nearest).
    fn from_f64(x: f64) -> Self;
    /// Conversion to f64 (exact).
    fn to_f64(self) -> f64;
    /// Is the value finite?
    fn is_finite(self) -> bool;
    /// Is the value NaN?
    fn is_nan(self) -> bool;
    /// Square root (correctly rounded).
    fn sqrt(self) -> Self;
}

macro_rules! impl_real {
    ($t:ty, $bits:ty, $mask:expr, $prec:expr, $var:ident) => {
        impl Real for $t {
            const PRECISION: Precision = $prec;
            const UNIT_ROUNDOFF: Self = <$t>::EPSILON / 2.0;
            const MIN_POSITIVE: Self = <$t>::MIN_POSITIVE;
            const MAX: Self = <$t>::MAX;
            const INFINITY: Self = <$t>::INFINITY;
            const NAN: Self = <$t>::NAN;
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
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
            fn is_nan(self) -> bool {
                <$t>::is_nan(self)
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
        }
        impl sealed::Sealed for $t {
            fn pack_spare() -> &'static std::thread::LocalKey<std::cell::RefCell<Vec<Self>>> {
                thread_local! {
                    static SPARE: std::cell::RefCell<Vec<$t>> = const { std::cell::RefCell::new(Vec::new()) };
                }
                &SPARE
            }
            const EXP_MASK: u64 = $mask;
            const TINY: Self = <$t>::from_bits(1);
            const WIDTH: u32 = <$bits>::BITS;
            #[inline(always)]
            fn bits(self) -> u64 {
                self.to_bits() as u64
            }
            #[inline(always)]
            fn from_bits64(b: u64) -> Self {
                <$t>::from_bits(b as $bits)
            }
            #[inline(always)]
            fn by_precision<F: sealed::Family>(x: F::Of<Self>) -> sealed::ByPrecision<F> {
                sealed::ByPrecision::$var(x)
            }
        }
    };
}
impl_real!(f32, u32, 0x7f80_0000, Precision::F32, F32);
impl_real!(f64, u64, 0x7ff0_0000_0000_0000, Precision::F64, F64);

#[cfg(test)]
mod tests {
    use super::sealed::Sealed;

    #[test]
    fn step_moves_one_ulp_in_either_direction() {
        assert_eq!(1.0f32.step(true), 1.0 + f32::EPSILON);
        assert_eq!(1.0f64.step(false), 1.0 - f64::EPSILON / 2.0);
        assert_eq!((-1.0f64).step(true), -1.0 + f64::EPSILON / 2.0);
        assert_eq!(0.0f32.step(true), f32::from_bits(1));
        assert_eq!(0.0f64.step(false), -f64::from_bits(1));
        assert_eq!(f64::INFINITY.step(false), f64::INFINITY);
        assert_eq!(f32::MAX.step(true), f32::INFINITY);
    }
}
