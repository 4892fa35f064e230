//! The `#[target_feature]` entry points of each x86-64 instruction set: one module per
//! instruction set, generated from the registry (`crate::query`) by [`simd_entries`].

use super::*;
use crate::algo::nodes::{Columns, Gaps, LeafTest, NodeTest};
use crate::arch::dispatch::{entry_modules, rare_modules, Entries};
use crate::drv::{Job, Pending};
use crate::query::{for_each_query, Query};

/// The entry points of one instruction set: for each query and precision a
/// `#[target_feature]` function instantiating the driver with the token's lane types, each in a
/// module of its own (`crate::arch::dispatch::entry_modules`). The last argument says where the rare paths
/// run (`crate::drv::accurate`, `crate::drv::recert`): `own` (entry points of this instruction
/// set, `crate::arch::dispatch::rare_modules`), `sse41` (AVX, whose bits are SSE4.1's: on SSE4.1, or the
/// portable code, the same bits, where detection does not find SSE4.1) or `avx2fma` (AVX-512VL,
/// whose bits and lanes are AVX2+FMA's).
macro_rules! simd_entries {
    ([($tok:ty), ($feat:literal), ($l32:ty), ($l64:ty), ($node:ty), ($acc:ident)] $($v:ident, $name:literal, $m:ident :: $k:ident, $about:literal;)*) => {
        entry_modules!(p32, f32, $tok, target_feature(enable = $feat), $l32, $($v, $m::$k;)*);
        entry_modules!(p64, f64, $tok, target_feature(enable = $feat), $l64, $($v, $m::$k;)*);
        rare_entries!($acc, $tok, $feat, $l32, $l64);
        impl Entries for $tok {
            fn accurate_f32(self, job: &mut Job<'_, f32>, open: &Pending<f32>, still: &mut Pending<f32>) {
                rare_on!($acc, self, accurate_f32, acc32, job, open, still)
            }
            fn accurate_f64(self, job: &mut Job<'_, f64>, open: &Pending<f64>, still: &mut Pending<f64>) {
                rare_on!($acc, self, accurate_f64, acc64, job, open, still)
            }
            fn recert_f32(self, job: &mut Job<'_, f32>, open: &Pending<f32>, still: &mut Pending<f32>, sharp: bool) {
                rare_on!($acc, self, recert_f32, rc32, job, open, still, sharp)
            }
            fn recert_f64(self, job: &mut Job<'_, f64>, open: &Pending<f64>, still: &mut Pending<f64>, sharp: bool) {
                rare_on!($acc, self, recert_f64, rc64, job, open, still, sharp)
            }
            fn run_f32(self, job: &mut Job<'_, f32>) {
                match job.query {
                    // SAFETY: `self` is a token of this instruction set: detection found every
                    // feature the entry point enables.
                    $(Query::$v => unsafe { p32::$v::run(self, job) },)*
                }
            }
            fn run_f64(self, job: &mut Job<'_, f64>) {
                match job.query {
                    // SAFETY: as above.
                    $(Query::$v => unsafe { p64::$v::run(self, job) },)*
                }
            }
            fn node_gaps(self, t: &NodeTest<'_>, out: &mut Gaps) {
                // SAFETY: as above.
                unsafe { node_gaps(self, t, out) }
            }
            fn node_columns(self, job: &mut Columns<'_>) {
                // SAFETY: as above.
                unsafe { node_columns(self, job) }
            }
            fn leaf_pairs(self, t: &LeafTest<'_>, out: &mut u64) {
                // SAFETY: as above.
                unsafe { leaf_pairs(self, t, out) }
            }
        }
        /// The mesh traversal's node test with the instruction set enabled.
        #[target_feature(enable = $feat)]
        fn node_gaps(k: $tok, t: &NodeTest<'_>, out: &mut Gaps) {
            crate::algo::nodes::gaps::<$node>(k, t, out)
        }
        /// The mesh traversal's moved node bounds with the instruction set enabled.
        #[target_feature(enable = $feat)]
        fn node_columns(k: $tok, job: &mut Columns<'_>) {
            crate::algo::nodes::columns::<$node>(k, job)
        }
        /// The mesh traversal's leaf test with the instruction set enabled.
        #[target_feature(enable = $feat)]
        fn leaf_pairs(k: $tok, t: &LeafTest<'_>, out: &mut u64) {
            crate::algo::nodes::leaf_pairs::<$node>(k, t, out)
        }
    };
}

/// The rare paths' entry points (`crate::arch::dispatch::rare_modules`) of an instruction set that
/// runs them itself (`own`).
macro_rules! rare_entries {
    (own, $tok:ty, $feat:literal, $l32:ty, $l64:ty) => {
        rare_modules!($tok, target_feature(enable = $feat), $l32, $l64);
    };
    ($other:ident, $tok:ty, $feat:literal, $l32:ty, $l64:ty) => {};
}

/// A rare path of a token's job (the accurate stage, the tight re-certification): its own entry
/// point (`own`), or the method of the same name on the token whose bits are the same
/// (`sse41`, falling back to the portable code; `avx2fma`).
macro_rules! rare_on {
    (own, $k:expr, $f:ident, $m:ident, $($a:ident),*) => {
        // SAFETY: `$k` is a token of this instruction set: detection found every feature the
        // entry point enables.
        unsafe { $m::run($k, $($a),*) }
    };
    (sse41, $k:expr, $f:ident, $m:ident, $($a:ident),*) => {
        match Sse41::detect() {
            Some(k) => k.$f($($a),*),
            None => crate::lanes::Portable.$f($($a),*),
        }
    };
    (avx2fma, $k:expr, $f:ident, $m:ident, $($a:ident),*) => {
        $k.avx2fma().$f($($a),*)
    };
}

// One module per instruction set: the compiler partitions code units by module, so the
// entry points of different instruction sets are optimised in parallel.
#[cfg(not(test))]
mod sse41 {
    use super::*;
    for_each_query!(simd_entries, (Sse41), ("sse4.1"), (F32x4<Sse41>), (F64x2<Sse41>), (F64x2<Sse41>), (own));
}
#[cfg(all(feature = "avx", not(test)))]
mod avx {
    use super::*;
    for_each_query!(simd_entries, (Avx), ("avx"), (F32x8<Avx>), (F64x4<Avx>), (F64x4<Avx>), (sse41));
}
mod avx2fma {
    use super::*;
    for_each_query!(
        simd_entries,
        (Avx2Fma),
        ("avx2,fma"),
        (F32x8<Avx2Fma>),
        (F64x4<Avx2Fma>),
        (F64x4<Avx2Fma>),
        (own)
    );
}
/// [`Avx2Fma`]'s vector types with AVX-512VL enabled: the same intrinsics, encoded with EVEX
/// where that helps, so the compiler has 32 vector registers instead of 16 (`Isa::Avx512Vl`).
#[cfg(all(feature = "avx512vl", not(test)))]
mod avx512vl {
    use super::*;
    for_each_query!(
        simd_entries,
        (Avx512Vl),
        ("avx512f,avx512vl,avx2,fma"),
        (F32x8<Avx512Vl>),
        (F64x4<Avx512Vl>),
        (F64x4<Avx512Vl>),
        (avx2fma)
    );
}
#[cfg(not(test))]
mod avx512 {
    use super::*;
    for_each_query!(
        simd_entries,
        (Avx512),
        ("avx512f,avx2,fma"),
        (F32x16<Avx512>),
        (F64x8<Avx512>),
        (F64x4<Avx512>),
        (own)
    );
}
