//! Instruction-set variants, runtime detection (once, cached), the capability tokens that
//! prove a variant is available, and the dispatch from a batch job to its entry point.

use std::sync::OnceLock;

use crate::algo::nodes::{Columns, Gaps, LeafTest, NodeTest};
use crate::drv::{Job, Pending};
use crate::query::{for_each_query, Query};

/// An instruction-set variant. Every variant runs the same algorithms (written once over a lane
/// trait); they differ in lane count and in whether `a*b+c` is fused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Isa {
    /// One lane, plain `f32`/`f64` arithmetic, never fused. Runs everywhere.
    Scalar,
    /// SSE4.1: f32x4, f64x2.
    Sse41,
    /// AVX without FMA: f32x8, f64x4. Compiled only with the crate feature `avx` (default off:
    /// it adds about a quarter to the build time; CPUs with AVX but not AVX2+FMA run
    /// [`Isa::Sse41`] then).
    Avx,
    /// AVX2 + FMA: f32x8, f64x4, fused multiply-add in every dot product.
    Avx2Fma,
    /// AVX-512 (F and VL) on 256-bit vectors: [`Isa::Avx2Fma`]'s f32x8 and f64x4, compiled with
    /// the 32 vector registers that AVX-512's encoding (EVEX) gives 256-bit instructions, where
    /// AVX2 has 16, so fewer values spill to the stack; bit for bit that variant's answers
    /// (tested). On the AMD EPYC (Zen 4) of the reports it runs f32 batches that the quick stage
    /// answers faster than [`Isa::Avx512`]'s 16 lanes (ARCHITECTURE.md, "Where the kernels'
    /// time goes"); mesh queries on [`Isa::Avx512`] run their small leaf batches and node
    /// tests on it. Compiled only with the crate feature `avx512vl` (default off: it adds about
    /// a fifth to the build time; without it those run on [`Isa::Avx2Fma`]).
    Avx512Vl,
    /// AVX-512 (F, with AVX2 and FMA): f32x16, f64x8, fused like [`Isa::Avx2Fma`], so every
    /// answer is bit for bit that variant's (tested); only the lane count differs. (Mesh
    /// queries on this variant run their small leaf batches and node tests on
    /// [`Isa::Avx512Vl`], or on [`Isa::Avx2Fma`] without that feature: 16 lanes were slower
    /// there.)
    Avx512,
}

impl Isa {
    /// Every variant, slowest first.
    pub const ALL: [Isa; 6] = [Isa::Scalar, Isa::Sse41, Isa::Avx, Isa::Avx2Fma, Isa::Avx512Vl, Isa::Avx512];

    /// Short name used by the CLI, the reports and `TRIDIST_ISA`.
    pub fn name(self) -> &'static str {
        match self {
            Isa::Scalar => "scalar",
            Isa::Sse41 => "sse41",
            Isa::Avx => "avx",
            Isa::Avx2Fma => "avx2fma",
            Isa::Avx512Vl => "avx512vl",
            Isa::Avx512 => "avx512",
        }
    }

    /// Parses [`Isa::name`].
    pub fn parse(s: &str) -> Option<Isa> {
        Isa::ALL.into_iter().find(|i| i.name() == s)
    }

    /// Lanes per vector for precision `T` (1 for scalar).
    pub fn lanes<T: crate::Real>(self) -> usize {
        let wide = match self {
            Isa::Scalar => return 1,
            Isa::Sse41 => 16,
            Isa::Avx | Isa::Avx2Fma | Isa::Avx512Vl => 32,
            Isa::Avx512 => 64,
        };
        wide / core::mem::size_of::<T>()
    }

    /// Does this CPU support the variant, and is it compiled in? (Runtime detection, cached.)
    pub fn is_available(self) -> bool {
        self.is_compiled() && detected()[self as usize]
    }

    /// Is the variant compiled into this build? Every variant except [`Isa::Avx`] and
    /// [`Isa::Avx512Vl`], which need the crate features `avx` and `avx512vl`.
    pub const fn is_compiled(self) -> bool {
        match self {
            Isa::Avx => cfg!(feature = "avx"),
            Isa::Avx512Vl => cfg!(feature = "avx512vl"),
            Isa::Scalar | Isa::Sse41 | Isa::Avx2Fma | Isa::Avx512 => true,
        }
    }

    /// The fastest available variant.
    pub fn best() -> Isa {
        *Isa::ALL.iter().rev().find(|i| i.is_available()).unwrap_or(&Isa::Scalar)
    }
}

impl core::fmt::Display for Isa {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

fn detected() -> &'static [bool; 6] {
    static D: OnceLock<[bool; 6]> = OnceLock::new();
    D.get_or_init(|| {
        #[cfg(target_arch = "x86_64")]
        {
            let sse = std::is_x86_feature_detected!("sse4.1");
            let avx = std::is_x86_feature_detected!("avx");
            let avx2fma =
                avx && std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma");
            let avx512 = avx2fma && std::is_x86_feature_detected!("avx512f");
            let avx512vl = avx512 && std::is_x86_feature_detected!("avx512vl");
            [true, sse, avx, avx2fma, avx512vl, avx512]
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            [true, false, false, false, false, false]
        }
    })
}

/// A capability token: a value exists only if this CPU runs the instruction set (the SIMD
/// tokens live in `crate::arch` with private fields, made only by detection). Running a job
/// needs one, so nothing reaches a `#[target_feature]` entry point without detection.
pub(crate) trait Token: Copy + 'static {
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

/// The token of the portable (scalar) variant: always available.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Portable;

/// The entry points of one instruction set and precision, generated from the registry: for
/// each query a function `run` (attribute `$attr`: the instruction set's `target_feature`, or
/// `inline(never)` for the portable code) instantiating the driver with the lane type `$l`, in a
/// module of its own (`p32::TriTri::run`). The compiler partitions codegen units by module and
/// merges only the smallest, so each large entry point is optimised in a unit of its own: the
/// build's peak memory is that of one entry point per parallel job, not of every query of an
/// instruction set at once (#17: the release build's peak fell from 1.29 to 0.95 GB; see
/// ARCHITECTURE.md "Compile-time budget").
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
pub(crate) use entry_modules;

/// The entry points of the rare paths, the accurate stage (`acc32::run`, `acc64::run`) and the
/// tight re-certification (`rc32::run`, `rc64::run`) of one instruction set, each in a module
/// of its own like [`entry_modules`]. Inlined into every query's entry point, these paths made
/// those functions so large that the optimiser's cost grew faster than their size (the stack
/// slots' promotion, ARCHITECTURE.md "Compile-time budget"): out of line, the kernels crate's
/// release build took half the CPU time. Two default-off variants run them on the variant
/// whose bits they share instead of compiling their own (AVX on SSE4.1's, AVX-512VL on
/// AVX2+FMA's; `crate::arch::x86_simd`'s `simd_entries`): every lane type evaluates the same
/// operations in the same order, and a lane's bits do not depend on the lane count
/// (`scenes/tests/bit_identity.rs`), so the answers are bit for bit their own.
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
        impl Token for Portable {
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
            match isa {
                Isa::Scalar => Portable.$fname($($a),*),
                #[cfg(target_arch = "x86_64")]
                Isa::Sse41 => on_detected!(crate::arch::x86_simd::Sse41, $fname, $($a),*),
                #[cfg(all(target_arch = "x86_64", feature = "avx"))]
                Isa::Avx => on_detected!(crate::arch::x86_simd::Avx, $fname, $($a),*),
                #[cfg(all(target_arch = "x86_64", not(feature = "avx")))]
                Isa::Avx => Portable.$fname($($a),*),
                #[cfg(target_arch = "x86_64")]
                Isa::Avx2Fma => on_detected!(crate::arch::x86_simd::Avx2Fma, $fname, $($a),*),
                #[cfg(all(target_arch = "x86_64", feature = "avx512vl"))]
                Isa::Avx512Vl => on_detected!(crate::arch::x86_simd::Avx512Vl, $fname, $($a),*),
                #[cfg(all(target_arch = "x86_64", not(feature = "avx512vl")))]
                Isa::Avx512Vl => Portable.$fname($($a),*),
                #[cfg(target_arch = "x86_64")]
                Isa::Avx512 => on_detected!(crate::arch::x86_simd::Avx512, $fname, $($a),*),
                #[cfg(not(target_arch = "x86_64"))]
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
