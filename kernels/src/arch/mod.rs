//! The ISA layer: which token's entry points an [`Isa`] runs (here, after runtime detection),
//! the entry points themselves (`dispatch`), and the x86-64 vector types implementing [`crate::lanes::Lanes`] with their
//! `#[target_feature]` entry points (`x86_simd`). Nothing here knows any geometry; this is the
//! only module of the crate with `unsafe` code (intrinsics and the calls of
//! `#[target_feature]` functions, each after runtime detection).

pub(crate) mod dispatch;
#[cfg(target_arch = "x86_64")]
pub(crate) mod x86_simd;

use crate::algo::nodes::{Columns, Gaps, LeafTest, NodeTest};
use crate::drv::Job;
use crate::isa::Isa;
use crate::lanes::Portable;
use crate::real::sealed::ByPrecision;
use crate::real::Real;
use dispatch::{Entries, JobOf};

/// The token method `$fname` on the token that runtime detection gives for `$tok` (one cached
/// load), or on the portable code when this CPU lacks it.
macro_rules! on_detected {
    ($tok:ty, $fname:ident, $($a:ident),*) => {
        match <$tok>::detect() {
            Some(k) => k.$fname($($a),*),
            None => Portable.$fname($($a),*),
        }
    };
}

macro_rules! run_for {
    ($fname:ident, $($a:ident: $ty:ty),*) => {
        /// Runs the token method of the same name on `isa` with a token from runtime detection
        /// (one cached load); a variant this CPU lacks runs the portable code instead.
        pub(crate) fn $fname(isa: Isa, $($a: $ty),*) {
            // (a variant not compiled in, and every variant in the unit tests' build but
            // AVX2+FMA, `Isa::is_compiled`: the portable code)
            match isa {
                #[cfg(target_arch = "x86_64")]
                Isa::Avx2Fma => on_detected!(crate::arch::x86_simd::Avx2Fma, $fname, $($a),*),
                #[cfg(all(target_arch = "x86_64", not(test)))]
                Isa::Sse41 => on_detected!(crate::arch::x86_simd::Sse41, $fname, $($a),*),
                #[cfg(all(target_arch = "x86_64", feature = "avx", not(test)))]
                Isa::Avx => on_detected!(crate::arch::x86_simd::Avx, $fname, $($a),*),
                #[cfg(all(target_arch = "x86_64", feature = "avx512vl", not(test)))]
                Isa::Avx512Vl => on_detected!(crate::arch::x86_simd::Avx512Vl, $fname, $($a),*),
                #[cfg(all(target_arch = "x86_64", not(test)))]
                Isa::Avx512 => on_detected!(crate::arch::x86_simd::Avx512, $fname, $($a),*),
                #[allow(unreachable_patterns)]
                _ => Portable.$fname($($a),*),
            }
        }
    };
}
run_for!(run_f32, job: &mut Job<'_, f32>);
run_for!(run_f64, job: &mut Job<'_, f64>);
run_for!(node_gaps, t: &NodeTest<'_>, out: &mut Gaps);
run_for!(node_columns, job: &mut Columns<'_>);
run_for!(leaf_pairs, t: &LeafTest<'_>, out: &mut u64);

/// Runs a batch job on the entry point of `isa` and its precision (a variant this CPU lacks
/// runs the portable code).
pub(crate) fn run<T: Real>(isa: Isa, job: &mut Job<'_, T>) {
    match T::by_precision::<JobOf<'_, '_>>(job) {
        ByPrecision::F32(job) => run_f32(isa, job),
        ByPrecision::F64(job) => run_f64(isa, job),
    }
}
