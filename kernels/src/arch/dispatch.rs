//! The entry points of an instruction set: the trait every capability token implements
//! ([`Entries`]), the macros that generate one `#[target_feature]` entry point per query,
//! precision and instruction set from the registry (`crate::query`), the portable entry
//! points, and the functions that run a generic job on a token's entry points. (Which token an
//! [`crate::Isa`] means is `crate::arch`'s.)
//!
//! The driver's escalation steps re-enter this module (a job's open pairs rerun as a sub-job
//! of another query or precision, on the same token): the one cycle of the crate's module
//! graph (ARCHITECTURE.md, "Modules").

use crate::algo::nodes::{Columns, Gaps, LeafTest, NodeTest};
use crate::drv::{Job, Pending};
use crate::lanes::{Portable, Token};
use crate::query::{for_each_query, Query};
use crate::real::sealed::{ByPrecision, Family};
use crate::real::Real;

/// The entry points of an instruction set, on its capability token ([`Token`]: a value exists
/// only if this CPU runs the instruction set; the SIMD tokens have private fields and are made
/// only by detection). Running a job needs one, so nothing reaches a `#[target_feature]` entry
/// point without detection.
pub(crate) trait Entries: Token {
    /// Runs an f32 job on this instruction set.
    fn run_f32(self, job: &mut Job<'_, f32>);
    /// Runs an f64 job on this instruction set.
    fn run_f64(self, job: &mut Job<'_, f64>);
    /// The accurate stage of triangle-triangle distance on an f32 job's open pairs
    /// ([`crate::drv::accurate`]), in an entry point of its own ([`rare_modules`]).
    fn accurate_f32(self, job: &mut Job<'_, f32>, open: &Pending<f32>, still: &mut Pending<f32>);
    /// The same for an f64 job.
    fn accurate_f64(self, job: &mut Job<'_, f64>, open: &Pending<f64>, still: &mut Pending<f64>);
    /// The tight re-certification of an f32 job's open pairs ([`crate::drv::recert`]), in an
    /// entry point of its own ([`rare_modules`]).
    fn recert_f32(self, job: &mut Job<'_, f32>, open: &Pending<f32>, still: &mut Pending<f32>, sharp: bool);
    /// The same for an f64 job.
    fn recert_f64(self, job: &mut Job<'_, f64>, open: &Pending<f64>, still: &mut Pending<f64>, sharp: bool);
    /// The mesh traversal's node test on this instruction set ([`crate::algo::nodes::gaps`]).
    fn node_gaps(self, t: &NodeTest<'_>, out: &mut Gaps);
    /// The mesh traversal's moved node bounds on this instruction set
    /// ([`crate::algo::nodes::columns`]).
    fn node_columns(self, job: &mut Columns<'_>);
    /// The mesh traversal's test of two leaves' triangle pairs on this instruction set
    /// ([`crate::algo::nodes::leaf_pairs`]).
    fn leaf_pairs(self, t: &LeafTest<'_>, out: &mut u64);
}

/// The entry points of one instruction set and precision, generated from the registry: for
/// each query a function `run` (attribute `$attr`: the instruction set's `target_feature`, or
/// `inline(never)` for the portable code) instantiating the driver with the lane type `$l`, in a
/// module of its own (`p32::TriTri::run`). The compiler starts with a codegen unit per module
/// and merges the smallest until the profile's `codegen-units` remain (16 by default in release):
/// then each unit holds four or five entry points of one instruction set and precision, not
/// every query of an instruction set at once, so the build's peak memory is that of a few entry
/// points per parallel job (the release build's peak fell from 1.29 to 0.95 GB; the partition,
/// `-Z print-mono-items=yes`, and the figures are in docs/notes/build-time.md).
macro_rules! entry_modules {
    ($p:ident, $t:ty, $tok:ty, $attr:meta, $l:ty, $($v:ident, $m:ident :: $k:ident;)*) => {
        mod $p {
            use super::*;
            $(
                #[allow(non_snake_case)]
                pub(super) mod $v {
                    use super::*;
                    #[$attr]
                    pub(in super::super) fn run(k: $tok, job: &mut Job<'_, $t>) {
                        crate::drv::run::<$l, crate::algo::$m::$k>(k, job)
                    }
                }
            )*
        }
    };
}

/// The entry points of the rare paths, the accurate stage (`acc32::run`, `acc64::run`) and the
/// tight re-certification (`rc32::run`, `rc64::run`) of one instruction set, each in a module
/// of its own like [`entry_modules`]. Inlined into every query's entry point, these paths made
/// those functions so large that the optimiser's cost grew faster than their size (the stack
/// slots' promotion, docs/notes/build-time.md): out of line, the kernels crate's
/// release build took half the CPU time. Two default-off variants run them on the variant
/// whose bits they share instead of compiling their own (AVX on SSE4.1's, AVX-512VL on
/// AVX2+FMA's; `crate::arch::x86_simd`'s `simd_entries`): every lane type evaluates the same
/// operations in the same order, and a lane's bits do not depend on the lane count
/// (`scenes/tests/bit_identity.rs`), so the answers are bit for bit their own.
pub(crate) use entry_modules;

macro_rules! rare_modules {
    ($tok:ty, $attr:meta, $l32:ty, $l64:ty) => {
        rare_modules!(@one acc32, $tok, $attr, f32, $l32, accurate);
        rare_modules!(@one acc64, $tok, $attr, f64, $l64, accurate);
        rare_modules!(@one rc32, $tok, $attr, f32, $l32, recert, sharp: bool);
        rare_modules!(@one rc64, $tok, $attr, f64, $l64, recert, sharp: bool);
    };
    (@one $m:ident, $tok:ty, $attr:meta, $t:ty, $l:ty, $f:ident $(, $x:ident: $xt:ty)?) => {
        mod $m {
            use super::*;
            #[$attr]
            pub(super) fn run(k: $tok, job: &mut Job<'_, $t>, open: &Pending<$t>, still: &mut Pending<$t> $(, $x: $xt)?) {
                crate::drv::$f::<$l>(k, job, open, still $(, $x)?)
            }
        }
    };
}

pub(crate) use rare_modules;

macro_rules! portable_entries {
    ([] $($v:ident, $name:literal, $m:ident :: $k:ident, $about:literal;)*) => {
        entry_modules!(p32, f32, Portable, inline(never), f32, $($v, $m::$k;)*);
        entry_modules!(p64, f64, Portable, inline(never), f64, $($v, $m::$k;)*);
        rare_modules!(Portable, inline(never), f32, f64);
        impl Entries for Portable {
            fn run_f32(self, job: &mut Job<'_, f32>) {
                match job.query {
                    $(Query::$v => p32::$v::run(self, job),)*
                }
            }
            fn run_f64(self, job: &mut Job<'_, f64>) {
                match job.query {
                    $(Query::$v => p64::$v::run(self, job),)*
                }
            }
            fn accurate_f32(self, job: &mut Job<'_, f32>, open: &Pending<f32>, still: &mut Pending<f32>) {
                acc32::run(self, job, open, still)
            }
            fn accurate_f64(self, job: &mut Job<'_, f64>, open: &Pending<f64>, still: &mut Pending<f64>) {
                acc64::run(self, job, open, still)
            }
            fn recert_f32(self, job: &mut Job<'_, f32>, open: &Pending<f32>, still: &mut Pending<f32>, sharp: bool) {
                rc32::run(self, job, open, still, sharp)
            }
            fn recert_f64(self, job: &mut Job<'_, f64>, open: &Pending<f64>, still: &mut Pending<f64>, sharp: bool) {
                rc64::run(self, job, open, still, sharp)
            }
            fn node_gaps(self, t: &NodeTest<'_>, out: &mut Gaps) {
                crate::algo::nodes::gaps::<f64>(self, t, out)
            }
            fn node_columns(self, job: &mut Columns<'_>) {
                crate::algo::nodes::columns::<f64>(self, job)
            }
            fn leaf_pairs(self, t: &LeafTest<'_>, out: &mut u64) {
                crate::algo::nodes::leaf_pairs::<f64>(self, t, out)
            }
        }
    };
}
mod portable {
    use super::*;
    for_each_query!(portable_entries);
}

/// A job of either precision (the [`Family`] of [`run`] and [`run_with`]).
pub(super) struct JobOf<'j, 'a>(core::marker::PhantomData<&'j mut Job<'a, ()>>);
impl<'j, 'a> Family for JobOf<'j, 'a> {
    type Of<T: 'static> = &'j mut Job<'a, T>;
}

/// A job and its open-pair lists (the [`Family`] of the rare paths).
struct RareOf<'j, 'a, 'o, 's>(core::marker::PhantomData<(&'j mut Job<'a, ()>, &'o (), &'s mut ())>);
impl<'j, 'a, 'o, 's> Family for RareOf<'j, 'a, 'o, 's> {
    type Of<T: 'static> = (&'j mut Job<'a, T>, &'o Pending<T>, &'s mut Pending<T>);
}

/// Runs a batch job on the entry point of the token `k` (an escalation step's sub-job, or a
/// single query on the portable code).
pub(crate) fn run_with<T: Real, K: Entries>(k: K, job: &mut Job<'_, T>) {
    match T::by_precision::<JobOf<'_, '_>>(job) {
        ByPrecision::F32(job) => k.run_f32(job),
        ByPrecision::F64(job) => k.run_f64(job),
    }
}

/// The accurate stage of a job's `open` pairs on the token `k` ([`crate::drv::accurate`]).
pub(crate) fn accurate_with<T: Real, K: Entries>(
    k: K,
    job: &mut Job<'_, T>,
    open: &Pending<T>,
    still: &mut Pending<T>,
) {
    match T::by_precision::<RareOf<'_, '_, '_, '_>>((job, open, still)) {
        ByPrecision::F32((job, open, still)) => k.accurate_f32(job, open, still),
        ByPrecision::F64((job, open, still)) => k.accurate_f64(job, open, still),
    }
}

/// The tight re-certification of a job's `open` pairs on the token `k` ([`crate::drv::recert`]).
pub(crate) fn recert_with<T: Real, K: Entries>(
    k: K,
    job: &mut Job<'_, T>,
    open: &Pending<T>,
    still: &mut Pending<T>,
    sharp: bool,
) {
    match T::by_precision::<RareOf<'_, '_, '_, '_>>((job, open, still)) {
        ByPrecision::F32((job, open, still)) => k.recert_f32(job, open, still, sharp),
        ByPrecision::F64((job, open, still)) => k.recert_f64(job, open, still, sharp),
    }
}
