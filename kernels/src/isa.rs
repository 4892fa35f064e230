//! Instruction-set variants and their runtime detection (once, cached). The capability tokens
//! that prove a variant available and the dispatch to its entry points are `crate::arch`'s.

use std::sync::OnceLock;

/// An instruction-set variant. Every variant runs the same algorithms (written once over a lane
/// trait); they differ in lane count and in whether `a*b+c` is fused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[non_exhaustive]
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
    /// (tested). Where the quick stage answers most pairs it can be faster than
    /// [`Isa::Avx512`]'s 16 lanes (`reports/THROUGHPUT.md` measures both on the report's CPU);
    /// mesh queries on [`Isa::Avx512`] run their small leaf batches and node tests on it.
    /// Compiled only with the crate feature `avx512vl` (default off for build time; without it
    /// those run on [`Isa::Avx2Fma`]).
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
        // The crate's own unit tests (`cfg(test)`: a second build of the crate, beside the
        // library the integration tests and the suite judge on every variant) compile the
        // query entry points of the portable code and AVX2+FMA only: they test the internals,
        // not each instruction set, and each set's entry points cost minutes to compile
        // (ARCHITECTURE.md, "Build-time rules").
        if cfg!(test) {
            return matches!(self, Isa::Scalar | Isa::Avx2Fma);
        }
        match self {
            Isa::Avx => cfg!(feature = "avx"),
            Isa::Avx512Vl => cfg!(feature = "avx512vl"),
            Isa::Scalar | Isa::Sse41 | Isa::Avx2Fma | Isa::Avx512 => true,
        }
    }

    /// Does this CPU run the variant's instructions (compiled in or not)? What a capability
    /// token proves.
    pub(crate) fn cpu_has(self) -> bool {
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
