//! Instruction-set variants, runtime detection (once, cached) and the engine that runs batches.

use std::sync::OnceLock;

use crate::driver::Job;

/// An instruction-set variant. Every variant runs the same algorithms (written once over a lane
/// trait); they differ in lane count and in whether `a*b+c` is fused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Isa {
    /// One lane, plain `f32`/`f64` arithmetic, never fused. Runs everywhere.
    Scalar,
    /// SSE4.1: f32x4, f64x2.
    Sse41,
    /// AVX without FMA: f32x8, f64x4.
    Avx,
    /// AVX2 + FMA: f32x8, f64x4, fused multiply-add in every dot product.
    Avx2Fma,
}

impl Isa {
    /// Every variant, slowest first.
    pub const ALL: [Isa; 4] = [Isa::Scalar, Isa::Sse41, Isa::Avx, Isa::Avx2Fma];

    /// Short name used by the CLI, the reports and `TRIDIST_ISA`.
    pub fn name(self) -> &'static str {
        match self {
            Isa::Scalar => "scalar",
            Isa::Sse41 => "sse41",
            Isa::Avx => "avx",
            Isa::Avx2Fma => "avx2fma",
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
            Isa::Avx | Isa::Avx2Fma => 32,
        };
        wide / core::mem::size_of::<T>()
    }

    /// Does this CPU support the variant? (Runtime detection, cached.)
    pub fn is_available(self) -> bool {
        detected()[self as usize]
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

fn detected() -> &'static [bool; 4] {
    static D: OnceLock<[bool; 4]> = OnceLock::new();
    D.get_or_init(|| {
        #[cfg(target_arch = "x86_64")]
        {
            let sse = std::is_x86_feature_detected!("sse4.1");
            let avx = std::is_x86_feature_detected!("avx");
            let avx2fma =
                avx && std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma");
            [true, sse, avx, avx2fma]
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            [true, false, false, false]
        }
    })
}

macro_rules! run_for {
    ($fname:ident, $t:ty, $sse:ident, $avx:ident, $fma:ident) => {
        /// Runs `job` on `isa`, after checking (one cached load) that this CPU supports it: an
        /// unavailable variant runs the scalar code instead, so no caller can reach a
        /// `#[target_feature]` entry point without detection.
        pub(crate) fn $fname(isa: Isa, job: &mut Job<'_, $t>) {
            let isa = if isa.is_available() { isa } else { Isa::Scalar };
            match isa {
                Isa::Scalar => crate::driver::run::<$t>(job),
                #[cfg(target_arch = "x86_64")]
                // SAFETY: Isa::is_available (runtime detection of sse4.1) was checked above.
                Isa::Sse41 => unsafe { crate::arch::x86::$sse(job) },
                #[cfg(target_arch = "x86_64")]
                // SAFETY: as above, avx was detected at run time.
                Isa::Avx => unsafe { crate::arch::x86::$avx(job) },
                #[cfg(target_arch = "x86_64")]
                // SAFETY: as above, avx2 and fma were detected at run time.
                Isa::Avx2Fma => unsafe { crate::arch::x86::$fma(job) },
                #[cfg(not(target_arch = "x86_64"))]
                _ => crate::driver::run::<$t>(job),
            }
        }
    };
}
run_for!(run_f32, f32, sse41_f32, avx_f32, avx2fma_f32);
run_for!(run_f64, f64, sse41_f64, avx_f64, avx2fma_f64);
