//! x86-64 vector types: SSE4.1 (f32x4, f64x2), AVX (f32x8, f64x4, with and without FMA) and
//! AVX-512F (f32x16, f64x8, fused; masks in `__mmask16` / `__mmask8`), their capability
//! tokens, and the `#[target_feature]` entry points, one per query, generated from the
//! registry (`crate::query`). Every vector type comes from the one `vec_type!` macro; AVX-512's
//! differently shaped operations (bit-mask blend, bitwise ops of floats) are supplied as small
//! wrappers in that shape, and its lane compaction uses the hardware gather.
//!
//! Soundness, by construction: a token (`Sse41`, `Avx`, `Avx2Fma`, `Avx512Vl`, `Avx512`) has a private field and is
//! made only by `detect()`, after runtime detection found its features. Every vector and mask
//! value carries its token (a zero-sized field) and every way to make one from nothing takes a
//! token, so holding a value proves the CPU runs its instructions: each `unsafe` intrinsic call
//! below is justified by the token of the value it operates on. The entry points enable the
//! features so that everything inlines into single instructions; an accidental call from
//! elsewhere would be slow, never undefined.
//!
//! (The module's name is long enough that its trait impls' legacy-mangled names sort after every
//! other function of the crate, so LLVM inlines these leaves last, top-down: see the module list
//! in `lib.rs`.)

use core::arch::x86_64::*;

use crate::algo::nodes::{Columns, Gaps, LeafTest, NodeTest};
use crate::drv::{Job, Pending};
use crate::isa::{entry_modules, rare_modules, Isa, Token};
use crate::lanes::{GatherIx, Lanes, Mask};
use crate::query::{for_each_query, Query};

/// Proof that SSE4.1 is available.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Sse41(());
/// Proof that AVX is available.
#[cfg(feature = "avx")]
#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx(());
/// Proof that AVX2 and FMA (and AVX) are available.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx2Fma(());
/// Proof that AVX-512F and AVX-512VL (and AVX2, FMA, AVX) are available.
#[cfg(feature = "avx512vl")]
#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx512Vl(());
/// Proof that AVX-512F (and AVX2, FMA, AVX) are available.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx512(());

impl Sse41 {
    /// A token when this CPU has SSE4.1 (cached detection).
    pub(crate) fn detect() -> Option<Self> {
        Isa::Sse41.is_available().then_some(Sse41(()))
    }
}
#[cfg(feature = "avx")]
impl Avx {
    /// A token when this CPU has AVX (cached detection).
    pub(crate) fn detect() -> Option<Self> {
        Isa::Avx.is_available().then_some(Avx(()))
    }
}
impl Avx2Fma {
    /// A token when this CPU has AVX, AVX2 and FMA (cached detection).
    pub(crate) fn detect() -> Option<Self> {
        Isa::Avx2Fma.is_available().then_some(Avx2Fma(()))
    }
}
#[cfg(feature = "avx512vl")]
impl Avx512Vl {
    /// A token when this CPU has AVX-512F, AVX-512VL, AVX2 and FMA (cached detection).
    pub(crate) fn detect() -> Option<Self> {
        Isa::Avx512Vl.is_available().then_some(Avx512Vl(()))
    }
}
impl Avx512 {
    /// A token when this CPU has AVX-512F, AVX2 and FMA (cached detection).
    pub(crate) fn detect() -> Option<Self> {
        Isa::Avx512.is_available().then_some(Avx512(()))
    }
}

#[cfg(feature = "avx512vl")]
impl Avx512Vl {
    /// The AVX2+FMA token this one implies (detection requires AVX2 and FMA for AVX-512VL).
    pub(crate) fn avx2fma(self) -> Avx2Fma {
        Avx2Fma(())
    }
}

/// Tokens that prove SSE4.1 (the 128-bit types).
pub(crate) trait HasSse41: Token {}
impl HasSse41 for Sse41 {}

/// Tokens that prove AVX (the 256-bit types); `FMA` when they also prove FMA.
pub(crate) trait HasAvx: Token {
    const FMA: bool;
    /// Does the token also prove AVX2 (the 256-bit integer instructions)?
    const AVX2: bool;
    /// Does the token also prove AVX-512F and VL (the 256-bit register compress)?
    const VL: bool = false;
}
#[cfg(feature = "avx")]
impl HasAvx for Avx {
    const FMA: bool = false;
    const AVX2: bool = false;
}
impl HasAvx for Avx2Fma {
    const FMA: bool = true;
    const AVX2: bool = true;
}
/// (AVX-512VL's entry points are the 256-bit types with 32 registers.)
#[cfg(feature = "avx512vl")]
impl HasAvx for Avx512Vl {
    const FMA: bool = true;
    const AVX2: bool = true;
    const VL: bool = true;
}
/// (The AVX-512 entry points run the mesh node test on the 256-bit types.)
impl HasAvx for Avx512 {
    const FMA: bool = true;
    const AVX2: bool = true;
}

/// Tokens that prove AVX-512F (the 512-bit types, always fused).
pub(crate) trait HasAvx512: Token {}
impl HasAvx512 for Avx512 {}

macro_rules! mask_type {
    ($name:ident, $cap:ident, $reg:ty, $and:ident, $or:ident, $andnot:ident, $xor:ident, $movemask:ident, $cast:ident, $set1:ident, $full:expr) => {
        #[derive(Clone, Copy)]
        pub(crate) struct $name<K>($reg, K);
        impl<K: $cap> Mask for $name<K> {
            #[inline(always)]
            fn and(self, o: Self) -> Self {
                // SAFETY: `self.1` is a token: detection found the instruction set (module docs).
                Self(unsafe { $and(self.0, o.0) }, self.1)
            }
            #[inline(always)]
            fn or(self, o: Self) -> Self {
                // SAFETY: `self.1` is a token: detection found the instruction set (module docs).
                Self(unsafe { $or(self.0, o.0) }, self.1)
            }
            #[inline(always)]
            fn andnot(self, o: Self) -> Self {
                // SAFETY: `self.1` is a token: detection found the instruction set (module docs).
                Self(unsafe { $andnot(o.0, self.0) }, self.1)
            }
            #[inline(always)]
            fn not(self) -> Self {
                // SAFETY: `self.1` is a token: detection found the instruction set (module docs).
                Self(unsafe { $xor(self.0, $cast($set1(-1))) }, self.1)
            }
            #[inline(always)]
            fn all(self) -> bool {
                // SAFETY: `self.1` is a token: detection found the instruction set (module docs).
                unsafe { $movemask(self.0) == $full }
            }
            #[inline(always)]
            fn any(self) -> bool {
                // SAFETY: `self.1` is a token: detection found the instruction set (module docs).
                unsafe { $movemask(self.0) != 0 }
            }
            #[inline(always)]
            fn bits(self) -> u32 {
                // SAFETY: `self.1` is a token: detection found the instruction set (module docs).
                unsafe { $movemask(self.0) as u32 }
            }
        }
    };
}

mask_type!(
    M32x4,
    HasSse41,
    __m128,
    _mm_and_ps,
    _mm_or_ps,
    _mm_andnot_ps,
    _mm_xor_ps,
    _mm_movemask_ps,
    _mm_castsi128_ps,
    _mm_set1_epi32,
    0xf
);
mask_type!(
    M64x2,
    HasSse41,
    __m128d,
    _mm_and_pd,
    _mm_or_pd,
    _mm_andnot_pd,
    _mm_xor_pd,
    _mm_movemask_pd,
    _mm_castsi128_pd,
    _mm_set1_epi32,
    0x3
);
mask_type!(
    M32x8,
    HasAvx,
    __m256,
    _mm256_and_ps,
    _mm256_or_ps,
    _mm256_andnot_ps,
    _mm256_xor_ps,
    _mm256_movemask_ps,
    _mm256_castsi256_ps,
    _mm256_set1_epi32,
    0xff
);
mask_type!(
    M64x4,
    HasAvx,
    __m256d,
    _mm256_and_pd,
    _mm256_or_pd,
    _mm256_andnot_pd,
    _mm256_xor_pd,
    _mm256_movemask_pd,
    _mm256_castsi256_pd,
    _mm256_set1_epi32,
    0xf
);

/// One `unsafe fn $name<K: $cap>(args: $reg...) -> $reg` per line, whose body runs under the
/// token's instruction set: the per-vector-type helpers of [`Lanes::max_exp`] and
/// [`Lanes::clamp01`] below.
///
/// # Safety
/// The CPU must run the instruction set of `K`'s token; the 256-bit forms use AVX2 only when
/// `K::AVX2`.
macro_rules! lane_fns {
    ($($name:ident, $cap:ident, $reg:ty, |$($a:ident),+| $body:expr;)*) => {$(
        #[inline(always)]
        unsafe fn $name<K: $cap>($($a: $reg),+) -> $reg {
            // SAFETY: the caller holds a token of `K` (see the macro's docs).
            unsafe { $body }
        }
    )*};
}

// The helpers behind [`Lanes::max_exp`], one per vector type: the integer maximum of the bit
// patterns (of each 32-bit half below AVX-512, whose high half holds an f64's exponent: the
// f64 forms there are not the maximum itself, `max_exp_exact = false`).
// Without AVX2 (the AVX variant) the 256-bit forms take the floating-point maximum and set
// every exponent bit of a lane where either operand is NaN (the maximum drops a NaN).
lane_fns!(
    max_exp128_ps, HasSse41, __m128, |a, b| _mm_castsi128_ps(_mm_max_epu32(_mm_castps_si128(a), _mm_castps_si128(b)));
    max_exp128_pd, HasSse41, __m128d, |a, b| _mm_castsi128_pd(_mm_max_epu32(_mm_castpd_si128(a), _mm_castpd_si128(b)));
    max_exp256_ps, HasAvx, __m256, |a, b| if K::AVX2 {
        _mm256_castsi256_ps(_mm256_max_epu32(_mm256_castps_si256(a), _mm256_castps_si256(b)))
    } else {
        let nan = _mm256_cmp_ps::<_CMP_UNORD_Q>(a, b);
        _mm256_or_ps(_mm256_max_ps(a, b), _mm256_and_ps(nan, _mm256_set1_ps(f32::INFINITY)))
    };
    max_exp256_pd, HasAvx, __m256d, |a, b| if K::AVX2 {
        _mm256_castsi256_pd(_mm256_max_epu32(_mm256_castpd_si256(a), _mm256_castpd_si256(b)))
    } else {
        let nan = _mm256_cmp_pd::<_CMP_UNORD_Q>(a, b);
        _mm256_or_pd(_mm256_max_pd(a, b), _mm256_and_pd(nan, _mm256_set1_pd(f64::INFINITY)))
    };
    max_exp512_ps, HasAvx512, __m512, |a, b| _mm512_castsi512_ps(_mm512_max_epu32(_mm512_castps_si512(a), _mm512_castps_si512(b)));
    max_exp512_pd, HasAvx512, __m512d, |a, b| _mm512_castsi512_pd(_mm512_max_epu64(_mm512_castpd_si512(a), _mm512_castpd_si512(b)));
);

// The helpers behind [`Lanes::clamp01`], one per vector type: where the hardware has a
// signed integer minimum and maximum of the lane's width (32-bit lanes from SSE4.1 on, 256-bit
// ones with AVX2; 64-bit lanes with AVX-512), the clamp of the bit patterns (one cycle each
// where the floating-point forms take four on Intel cores, by published instruction tables;
// the edge pair's three clamps are on the quick stage's critical path). Non-negative floats
// order as their patterns, negative ones (sign bit set) as negative integers, so for every
// non-NaN input the result is the floating-point clamp's, bit for bit (`-0` and negatives
// give `+0`). The other forms take the floating-point clamp. (NaN never reaches a clamp:
// divisions are guarded.)
lane_fns!(
    clamp128_ps, HasSse41, __m128, |a| _mm_castsi128_ps(_mm_min_epi32(
        _mm_max_epi32(_mm_castps_si128(a), _mm_setzero_si128()),
        _mm_set1_epi32(1.0f32.to_bits() as i32)
    ));
    clamp128_pd, HasSse41, __m128d, |a| _mm_min_pd(_mm_max_pd(a, _mm_setzero_pd()), _mm_set1_pd(1.0));
    clamp256_ps, HasAvx, __m256, |a| if K::AVX2 {
        _mm256_castsi256_ps(_mm256_min_epi32(
            _mm256_max_epi32(_mm256_castps_si256(a), _mm256_setzero_si256()),
            _mm256_set1_epi32(1.0f32.to_bits() as i32),
        ))
    } else {
        _mm256_min_ps(_mm256_max_ps(a, _mm256_setzero_ps()), _mm256_set1_ps(1.0))
    };
    clamp256_pd, HasAvx, __m256d, |a| _mm256_min_pd(_mm256_max_pd(a, _mm256_setzero_pd()), _mm256_set1_pd(1.0));
    clamp512_ps, HasAvx512, __m512, |a| _mm512_castsi512_ps(_mm512_min_epi32(
        _mm512_max_epi32(_mm512_castps_si512(a), _mm512_setzero_si512()),
        _mm512_set1_epi32(1.0f32.to_bits() as i32)
    ));
    clamp512_pd, HasAvx512, __m512d, |a| _mm512_castsi512_pd(_mm512_min_epi64(
        _mm512_max_epi64(_mm512_castpd_si512(a), _mm512_setzero_si512()),
        _mm512_set1_epi64(1.0f64.to_bits() as i64)
    ));
);

/// One vector type over a token `K: $cap`; `mul_add` is fused when `$fma` holds for `K`.
macro_rules! vec_type {
    (
        $name:ident, $cap:ident, $fma:expr, $s:ty, $n:expr, $reg:ty, $mask:ident,
        set1 = $set1:ident, loadu = $loadu:ident, storeu = $storeu:ident,
        add = $add:ident, sub = $sub:ident, mul = $mul:ident, div = $div:ident,
        min = $min:ident, max = $max:ident, sqrt = $sqrt:ident, and = $and:ident,
        andnot = $andnot:ident, blendv = $blendv:ident, fmadd = $fmadd:ident,
        lt = $lt:expr, le = $le:expr, eq = $eq:expr, bits = $bits:ty,
        max_exp = $max_exp:ident, max_exp_exact = $exact:expr, clamp01 = $clamp01:ident
        $(, gather = $gather:ident)? $(, compress = $compress:ident, compress_on = $con:expr)?
    ) => {
        #[derive(Clone, Copy)]
        pub(crate) struct $name<K>($reg, K);
        impl<K: $cap> Lanes for $name<K> {
            type S = $s;
            type M = $mask<K>;
            type K = K;
            const N: usize = $n;
            type Arr = [$s; $n];
            const ZEROS: [$s; $n] = [0.0; $n];
            const FMA: bool = $fma;
            #[inline(always)]
            fn token(self) -> K {
                self.1
            }
            #[inline(always)]
            fn splat(k: K, s: $s) -> Self {
                // SAFETY: `k` is a token: detection found the instruction set (module docs).
                Self(unsafe { $set1(s) }, k)
            }
            #[inline(always)]
            fn load(k: K, src: &[$s]) -> Self {
                let src = &src[..$n];
                // SAFETY: `src` has exactly N readable elements (checked by the slice above);
                // `k` is a token: detection found the instruction set (module docs).
                Self(unsafe { $loadu(src.as_ptr()) }, k)
            }
            #[inline(always)]
            fn store(self, dst: &mut [$s]) {
                let dst = &mut dst[..$n];
                // SAFETY: `dst` has exactly N writable elements; `self.1` is a token (module docs).
                unsafe { $storeu(dst.as_mut_ptr(), self.0) }
            }
            #[inline(always)]
            fn add(self, o: Self) -> Self {
                // SAFETY: `self.1` is a token: detection found the instruction set (module docs).
                Self(unsafe { $add(self.0, o.0) }, self.1)
            }
            #[inline(always)]
            fn sub(self, o: Self) -> Self {
                // SAFETY: `self.1` is a token: detection found the instruction set (module docs).
                Self(unsafe { $sub(self.0, o.0) }, self.1)
            }
            #[inline(always)]
            fn mul(self, o: Self) -> Self {
                // SAFETY: `self.1` is a token: detection found the instruction set (module docs).
                Self(unsafe { $mul(self.0, o.0) }, self.1)
            }
            #[inline(always)]
            fn div(self, o: Self) -> Self {
                // SAFETY: `self.1` is a token: detection found the instruction set (module docs).
                Self(unsafe { $div(self.0, o.0) }, self.1)
            }
            #[inline(always)]
            fn mul_add(self, b: Self, c: Self) -> Self {
                if $fma {
                    // SAFETY: `$fma` holds only for tokens that prove FMA (`Avx2Fma`,
                    // `Avx512`): detection found it (module docs).
                    Self(unsafe { $fmadd(self.0, b.0, c.0) }, self.1)
                } else {
                    self.mul(b).add(c)
                }
            }
            #[inline(always)]
            fn min(self, o: Self) -> Self {
                // SAFETY: `self.1` is a token: detection found the instruction set (module docs).
                Self(unsafe { $min(self.0, o.0) }, self.1)
            }
            #[inline(always)]
            fn max(self, o: Self) -> Self {
                // SAFETY: `self.1` is a token: detection found the instruction set (module docs).
                Self(unsafe { $max(self.0, o.0) }, self.1)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                // SAFETY: `self.1` is a token: detection found the instruction set (module docs).
                Self(unsafe { $andnot($set1(-0.0), self.0) }, self.1)
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                // SAFETY: `self.1` is a token: detection found the instruction set (module docs).
                Self(unsafe { $sqrt(self.0) }, self.1)
            }
            #[inline(always)]
            fn lt(self, o: Self) -> $mask<K> {
                // SAFETY: `self.1` is a token: detection found the instruction set (module docs).
                $mask(unsafe { $lt(self.0, o.0) }, self.1)
            }
            #[inline(always)]
            fn le(self, o: Self) -> $mask<K> {
                // SAFETY: `self.1` is a token: detection found the instruction set (module docs).
                $mask(unsafe { $le(self.0, o.0) }, self.1)
            }
            #[inline(always)]
            fn eq(self, o: Self) -> $mask<K> {
                // SAFETY: `self.1` is a token: detection found the instruction set (module docs).
                $mask(unsafe { $eq(self.0, o.0) }, self.1)
            }
            #[inline(always)]
            fn select(m: $mask<K>, t: Self, f: Self) -> Self {
                // SAFETY: `t.1` is a token: detection found the instruction set (module docs).
                Self(unsafe { $blendv(f.0, t.0, m.0) }, t.1)
            }
            #[inline(always)]
            fn exponent(self) -> Self {
                use crate::real::sealed::Sealed;
                let m = <$s>::from_bits(<$s as Sealed>::EXP_MASK as $bits);
                // SAFETY: `self.1` is a token: detection found the instruction set (module docs).
                Self(unsafe { $and(self.0, $set1(m)) }, self.1)
            }
            #[inline(always)]
            fn recip_exponent(self) -> Self {
                use crate::real::sealed::Sealed;
                let m = <$s>::from_bits(<$s as Sealed>::EXP_MASK as $bits);
                // SAFETY: `self.1` is a token: detection found the instruction set (module docs).
                Self(unsafe { $mul($andnot(self.0, $set1(m)), $set1(0.5)) }, self.1)
            }
            const MAX_EXP_EXACT: bool = $exact;
            #[inline(always)]
            fn max_exp(self, o: Self) -> Self {
                // SAFETY: `self.1` is a token of `K`, whose instruction set `$max_exp` checks
                // before using anything beyond it (module docs).
                Self(unsafe { $max_exp::<K>(self.0, o.0) }, self.1)
            }
            #[inline(always)]
            fn clamp01(self) -> Self {
                // SAFETY: `self.1` is a token of `K`, whose instruction set `$clamp01` checks
                // before using anything beyond it (module docs).
                Self(unsafe { $clamp01::<K>(self.0) }, self.1)
            }
            $(
                #[inline(always)]
                fn gather(k: K, col: &[$s], ix: &GatherIx) -> Self {
                    match $gather(k, col, ix) {
                        Some(v) => Self(v, k),
                        None => crate::lanes::gather_lanes(k, col, ix),
                    }
                }
            )?
            $(
                const COMPRESS: bool = $con;
                #[inline(always)]
                fn compress(self, m: u32, dst: &mut [$s]) {
                    if $con {
                        $compress(self.1, self.0, m, &mut dst[..$n]);
                    } else {
                        crate::lanes::compress_lanes(self, m, dst);
                    }
                }
            )?
        }
    };
}

vec_type!(
    F32x4,
    HasSse41,
    false,
    f32,
    4,
    __m128,
    M32x4,
    set1 = _mm_set1_ps,
    loadu = _mm_loadu_ps,
    storeu = _mm_storeu_ps,
    add = _mm_add_ps,
    sub = _mm_sub_ps,
    mul = _mm_mul_ps,
    div = _mm_div_ps,
    min = _mm_min_ps,
    max = _mm_max_ps,
    sqrt = _mm_sqrt_ps,
    and = _mm_and_ps,
    andnot = _mm_andnot_ps,
    blendv = _mm_blendv_ps,
    fmadd = _mm_fmadd_ps,
    lt = _mm_cmplt_ps,
    le = _mm_cmple_ps,
    eq = _mm_cmpeq_ps,
    bits = u32,
    max_exp = max_exp128_ps,
    max_exp_exact = true,
    clamp01 = clamp128_ps
);
vec_type!(
    F64x2,
    HasSse41,
    false,
    f64,
    2,
    __m128d,
    M64x2,
    set1 = _mm_set1_pd,
    loadu = _mm_loadu_pd,
    storeu = _mm_storeu_pd,
    add = _mm_add_pd,
    sub = _mm_sub_pd,
    mul = _mm_mul_pd,
    div = _mm_div_pd,
    min = _mm_min_pd,
    max = _mm_max_pd,
    sqrt = _mm_sqrt_pd,
    and = _mm_and_pd,
    andnot = _mm_andnot_pd,
    blendv = _mm_blendv_pd,
    fmadd = _mm_fmadd_pd,
    lt = _mm_cmplt_pd,
    le = _mm_cmple_pd,
    eq = _mm_cmpeq_pd,
    bits = u64,
    max_exp = max_exp128_pd,
    max_exp_exact = false,
    clamp01 = clamp128_pd
);
vec_type!(
    F32x8,
    HasAvx,
    K::FMA,
    f32,
    8,
    __m256,
    M32x8,
    set1 = _mm256_set1_ps,
    loadu = _mm256_loadu_ps,
    storeu = _mm256_storeu_ps,
    add = _mm256_add_ps,
    sub = _mm256_sub_ps,
    mul = _mm256_mul_ps,
    div = _mm256_div_ps,
    min = _mm256_min_ps,
    max = _mm256_max_ps,
    sqrt = _mm256_sqrt_ps,
    and = _mm256_and_ps,
    andnot = _mm256_andnot_ps,
    blendv = _mm256_blendv_ps,
    fmadd = _mm256_fmadd_ps,
    lt = _mm256_cmp_ps::<_CMP_LT_OQ>,
    le = _mm256_cmp_ps::<_CMP_LE_OQ>,
    eq = _mm256_cmp_ps::<_CMP_EQ_OQ>,
    bits = u32,
    max_exp = max_exp256_ps,
    max_exp_exact = true,
    clamp01 = clamp256_ps,
    compress = compress256_ps,
    compress_on = K::VL
);
vec_type!(
    F64x4,
    HasAvx,
    K::FMA,
    f64,
    4,
    __m256d,
    M64x4,
    set1 = _mm256_set1_pd,
    loadu = _mm256_loadu_pd,
    storeu = _mm256_storeu_pd,
    add = _mm256_add_pd,
    sub = _mm256_sub_pd,
    mul = _mm256_mul_pd,
    div = _mm256_div_pd,
    min = _mm256_min_pd,
    max = _mm256_max_pd,
    sqrt = _mm256_sqrt_pd,
    and = _mm256_and_pd,
    andnot = _mm256_andnot_pd,
    blendv = _mm256_blendv_pd,
    fmadd = _mm256_fmadd_pd,
    lt = _mm256_cmp_pd::<_CMP_LT_OQ>,
    le = _mm256_cmp_pd::<_CMP_LE_OQ>,
    eq = _mm256_cmp_pd::<_CMP_EQ_OQ>,
    bits = u64,
    max_exp = max_exp256_pd,
    max_exp_exact = false,
    clamp01 = clamp256_pd,
    compress = compress256_pd,
    compress_on = K::VL
);

/// An AVX-512 comparison mask: one bit per lane in a `__mmask16` / `__mmask8` (plain integer
/// operations: no intrinsic, no `unsafe`).
macro_rules! kmask_type {
    ($name:ident, $bits:ty) => {
        #[derive(Clone, Copy)]
        pub(crate) struct $name<K>($bits, K);
        impl<K: HasAvx512> Mask for $name<K> {
            #[inline(always)]
            fn and(self, o: Self) -> Self {
                Self(self.0 & o.0, self.1)
            }
            #[inline(always)]
            fn or(self, o: Self) -> Self {
                Self(self.0 | o.0, self.1)
            }
            #[inline(always)]
            fn andnot(self, o: Self) -> Self {
                Self(self.0 & !o.0, self.1)
            }
            #[inline(always)]
            fn not(self) -> Self {
                Self(!self.0, self.1)
            }
            #[inline(always)]
            fn all(self) -> bool {
                self.0 == <$bits>::MAX
            }
            #[inline(always)]
            fn any(self) -> bool {
                self.0 != 0
            }
            #[inline(always)]
            fn bits(self) -> u32 {
                self.0 as u32
            }
        }
    };
}
kmask_type!(M32x16, __mmask16);
kmask_type!(M64x8, __mmask8);

/// The AVX-512 forms of the operations [`vec_type!`] takes in the SSE/AVX shape: a blend by a
/// bit mask with the operands in `blendv` order, and bitwise and / and-not of floats (AVX-512F
/// has them on integers). Called only inside the AVX-512 entry points, like every lane method.
macro_rules! avx512_forms {
    ($reg:ty, $m:ty, $blendv:ident, $and:ident, $andnot:ident, $blend:ident, $to:ident, $from:ident) => {
        /// `m ? t : f` per lane.
        ///
        /// # Safety
        /// AVX-512F must be available (a token's caller).
        #[inline(always)]
        unsafe fn $blendv(f: $reg, t: $reg, m: $m) -> $reg {
            // SAFETY: the caller holds a token of AVX-512F.
            unsafe { $blend(m, f, t) }
        }
        /// `a & b` bitwise.
        ///
        /// # Safety
        /// AVX-512F must be available (a token's caller).
        #[inline(always)]
        unsafe fn $and(a: $reg, b: $reg) -> $reg {
            // SAFETY: the caller holds a token of AVX-512F.
            unsafe { $from(_mm512_and_si512($to(a), $to(b))) }
        }
        /// `!a & b` bitwise.
        ///
        /// # Safety
        /// AVX-512F must be available (a token's caller).
        #[inline(always)]
        unsafe fn $andnot(a: $reg, b: $reg) -> $reg {
            // SAFETY: the caller holds a token of AVX-512F.
            unsafe { $from(_mm512_andnot_si512($to(a), $to(b))) }
        }
    };
}
/// The hardware gather of `col[at[l]]` into lane `l` (`$n` lanes, 32-bit offsets in `$ix`).
/// `None` when an offset is out of bounds or the column too long for 32-bit offsets: the
/// caller then gathers lane by lane (and panics on the bad index, as indexing does). On the
/// Zen 5 reference machine, `spin tri_tri random f32 avx512 1.5` (three quarters of the pairs
/// gathered for the full fast stage) ran at 37.3-37.5 M/s with it and 32.1-32.8 without (two
/// copies of each binary, alternated twice); f64 was unchanged (26.5-27.0 either way). Since
/// then the full fast stage reads those pairs packed by the quick stage's register compress
/// instead (`crate::drv::Packed`, faster still); the gather serves the rare paths
/// (re-certification, the accurate stage) and the sub-jobs of escalation.
macro_rules! gather512 {
    ($name:ident, $s:ty, $reg:ty, $n:expr, $ix:ty, $load_ix:ident, $gather:ident, $scale:expr) => {
        #[inline(always)]
        fn $name<K: HasAvx512>(_: K, col: &[$s], ix: &GatherIx) -> Option<$reg> {
            if ix.top >= col.len() || col.len() > i32::MAX as usize {
                return None;
            }
            // SAFETY: every offset is at most `ix.top`, below `col.len()` (checked above),
            // and `ix.off` holds them exactly as `col.len()` fits in i32, so each lane reads an
            // element of `col`; `ix.off` has at least the index vector's size; the first
            // argument is a token: detection found AVX-512F (module docs).
            Some(unsafe {
                let ix: $ix = $load_ix(ix.off.as_ptr().cast());
                $gather::<$scale>(ix, col.as_ptr().cast())
            })
        }
    };
}
gather512!(gather512_ps, f32, __m512, 16, __m512i, _mm512_loadu_si512, _mm512_i32gather_ps, 4);
gather512!(gather512_pd, f64, __m512d, 8, __m256i, _mm256_loadu_si256, _mm512_i32gather_pd, 8);

/// The register compress of the lanes set in `m` to the front, stored as `$n` values.
macro_rules! compress512 {
    ($name:ident, $s:ty, $reg:ty, $n:expr, $mask:ty, $compress:ident, $storeu:ident) => {
        #[inline(always)]
        fn $name<K: HasAvx512>(_: K, v: $reg, m: u32, dst: &mut [$s]) {
            let dst = &mut dst[..$n];
            // SAFETY: `dst` has exactly `$n` writable elements (checked by the slice above);
            // the first argument is a token: detection found AVX-512F (module docs).
            unsafe { $storeu(dst.as_mut_ptr(), $compress(m as $mask, v)) }
        }
    };
}
compress512!(compress512_ps, f32, __m512, 16, __mmask16, _mm512_maskz_compress_ps, _mm512_storeu_ps);
compress512!(compress512_pd, f64, __m512d, 8, __mmask8, _mm512_maskz_compress_pd, _mm512_storeu_pd);

/// The 256-bit register compress of AVX-512VL, for [`HasAvx::VL`] tokens only.
macro_rules! compress256 {
    ($name:ident, $s:ty, $reg:ty, $n:expr, $compress:ident, $storeu:ident) => {
        #[inline(always)]
        fn $name<K: HasAvx>(_: K, v: $reg, m: u32, dst: &mut [$s]) {
            assert!(K::VL);
            let dst = &mut dst[..$n];
            // SAFETY: `dst` has exactly `$n` writable elements (checked by the slice above);
            // the first argument is a token proving AVX-512F and VL (`K::VL`, asserted above;
            // the callers test it first, so the assertion folds away).
            unsafe { $storeu(dst.as_mut_ptr(), $compress(m as u8, v)) }
        }
    };
}
compress256!(compress256_ps, f32, __m256, 8, _mm256_maskz_compress_ps, _mm256_storeu_ps);
compress256!(compress256_pd, f64, __m256d, 4, _mm256_maskz_compress_pd, _mm256_storeu_pd);

avx512_forms!(
    __m512,
    __mmask16,
    blendv512_ps,
    and512_ps,
    andnot512_ps,
    _mm512_mask_blend_ps,
    _mm512_castps_si512,
    _mm512_castsi512_ps
);
avx512_forms!(
    __m512d,
    __mmask8,
    blendv512_pd,
    and512_pd,
    andnot512_pd,
    _mm512_mask_blend_pd,
    _mm512_castpd_si512,
    _mm512_castsi512_pd
);

vec_type!(
    F32x16,
    HasAvx512,
    true,
    f32,
    16,
    __m512,
    M32x16,
    set1 = _mm512_set1_ps,
    loadu = _mm512_loadu_ps,
    storeu = _mm512_storeu_ps,
    add = _mm512_add_ps,
    sub = _mm512_sub_ps,
    mul = _mm512_mul_ps,
    div = _mm512_div_ps,
    min = _mm512_min_ps,
    max = _mm512_max_ps,
    sqrt = _mm512_sqrt_ps,
    and = and512_ps,
    andnot = andnot512_ps,
    blendv = blendv512_ps,
    fmadd = _mm512_fmadd_ps,
    lt = _mm512_cmp_ps_mask::<_CMP_LT_OQ>,
    le = _mm512_cmp_ps_mask::<_CMP_LE_OQ>,
    eq = _mm512_cmp_ps_mask::<_CMP_EQ_OQ>,
    bits = u32,
    max_exp = max_exp512_ps,
    max_exp_exact = true,
    clamp01 = clamp512_ps,
    gather = gather512_ps,
    compress = compress512_ps,
    compress_on = true
);
vec_type!(
    F64x8,
    HasAvx512,
    true,
    f64,
    8,
    __m512d,
    M64x8,
    set1 = _mm512_set1_pd,
    loadu = _mm512_loadu_pd,
    storeu = _mm512_storeu_pd,
    add = _mm512_add_pd,
    sub = _mm512_sub_pd,
    mul = _mm512_mul_pd,
    div = _mm512_div_pd,
    min = _mm512_min_pd,
    max = _mm512_max_pd,
    sqrt = _mm512_sqrt_pd,
    and = and512_pd,
    andnot = andnot512_pd,
    blendv = blendv512_pd,
    fmadd = _mm512_fmadd_pd,
    lt = _mm512_cmp_pd_mask::<_CMP_LT_OQ>,
    le = _mm512_cmp_pd_mask::<_CMP_LE_OQ>,
    eq = _mm512_cmp_pd_mask::<_CMP_EQ_OQ>,
    bits = u64,
    max_exp = max_exp512_pd,
    max_exp_exact = true,
    clamp01 = clamp512_pd,
    gather = gather512_pd,
    compress = compress512_pd,
    compress_on = true
);

/// The entry points of one instruction set: for each query and precision a
/// `#[target_feature]` function instantiating the driver with the token's lane types, each in a
/// module of its own (`crate::isa::entry_modules`). The last argument says where the rare paths
/// run (`crate::drv::accurate`, `crate::drv::recert`): `own` (entry points of this instruction
/// set, `crate::isa::rare_modules`), `sse41` (AVX, whose bits are SSE4.1's: on SSE4.1, or the
/// portable code, the same bits, where detection does not find SSE4.1) or `avx2fma` (AVX-512VL,
/// whose bits and lanes are AVX2+FMA's).
macro_rules! simd_entries {
    ([($tok:ty), ($feat:literal), ($l32:ty), ($l64:ty), ($node:ty), ($acc:ident)] $($v:ident, $name:literal, $m:ident :: $k:ident, $about:literal;)*) => {
        entry_modules!(p32, f32, $tok, target_feature(enable = $feat), $l32, $($v, $m::$k;)*);
        entry_modules!(p64, f64, $tok, target_feature(enable = $feat), $l64, $($v, $m::$k;)*);
        rare_entries!($acc, $tok, $feat, $l32, $l64);
        impl Token for $tok {
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

/// The rare paths' entry points (`crate::isa::rare_modules`) of an instruction set that
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
            None => crate::isa::Portable.$f($($a),*),
        }
    };
    (avx2fma, $k:expr, $f:ident, $m:ident, $($a:ident),*) => {
        $k.avx2fma().$f($($a),*)
    };
}

// One module per instruction set: the compiler partitions code units by module, so the
// entry points of different instruction sets are optimised in parallel.
mod sse41 {
    use super::*;
    for_each_query!(simd_entries, (Sse41), ("sse4.1"), (F32x4<Sse41>), (F64x2<Sse41>), (F64x2<Sse41>), (own));
}
#[cfg(feature = "avx")]
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
#[cfg(feature = "avx512vl")]
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::isa::Portable;
    use crate::lanes::{MAX_LANES, V3};
    use crate::real::sealed::Sealed;
    use crate::real::Real;

    /// Every exponent field (subnormals, normals, inf and NaN) with four mantissas and both signs.
    fn samples<S: Real>() -> Vec<S> {
        let mant = S::EXP_MASK.trailing_zeros();
        let mut out = Vec::new();
        for e in 0..=S::EXP_MASK >> mant {
            for m in [0, 1, 1 << (mant - 1), (1 << mant) - 1] {
                for sign in [0, 1 << (S::WIDTH - 1)] {
                    out.push(S::from_bits64(sign | e << mant | m));
                }
            }
        }
        out
    }

    /// Runs `$check::<L>(token)` for every vector type whose instruction set this CPU has (each
    /// test runs the scalar types itself, with the count it expects).
    macro_rules! on_every_vector_type {
        ($check:ident) => {
            if let Some(k) = Sse41::detect() {
                $check::<F32x4<Sse41>>(k);
                $check::<F64x2<Sse41>>(k);
            }
            #[cfg(feature = "avx")]
            if let Some(k) = Avx::detect() {
                $check::<F32x8<Avx>>(k);
                $check::<F64x4<Avx>>(k);
            }
            if let Some(k) = Avx2Fma::detect() {
                $check::<F32x8<Avx2Fma>>(k);
                $check::<F64x4<Avx2Fma>>(k);
            }
            #[cfg(feature = "avx512vl")]
            if let Some(k) = Avx512Vl::detect() {
                $check::<F32x8<Avx512Vl>>(k);
                $check::<F64x4<Avx512Vl>>(k);
            }
            if let Some(k) = Avx512::detect() {
                $check::<F32x16<Avx512>>(k);
                $check::<F64x8<Avx512>>(k);
            }
        };
    }

    /// `recip_exponent` is `1 / exponent` bit for bit, lane by lane, for every input.
    fn recip_exponent_is_exact<L: Lanes>(k: L::K) -> usize {
        let xs = samples::<L::S>();
        for part in xs.chunks(L::N) {
            let mut buf = [L::S::ZERO; MAX_LANES];
            buf[..part.len()].copy_from_slice(part);
            let x = L::load(k, &buf);
            let (mut got, mut want) = ([L::S::ZERO; MAX_LANES], [L::S::ZERO; MAX_LANES]);
            x.recip_exponent().store(&mut got);
            L::splat(k, L::S::ONE).div(x.exponent()).store(&mut want);
            for (l, &xl) in part.iter().enumerate() {
                assert_eq!(got[l].bits(), want[l].bits(), "{} lanes, input bits {:#x}", L::N, xl.bits());
            }
        }
        xs.len()
    }

    /// `max_exp` of two non-negative values has the larger exponent field, a clear sign, and
    /// all exponent bits set exactly when either operand's are (inf or NaN), lane by lane; it
    /// is the larger value itself for finite operands where the type says so
    /// (`MAX_EXP_EXACT`).
    /// Every non-negative sample against every one a fixed stride away, for several strides.
    fn max_exp_takes_the_larger_exponent<L: Lanes>(k: L::K) -> usize {
        let xs: Vec<L::S> =
            samples::<L::S>().into_iter().filter(|x| x.bits() >> (L::S::WIDTH - 1) == 0).collect();
        let field = |x: L::S| x.bits() & L::S::EXP_MASK;
        let mut checked = 0;
        for stride in [0, 1, 3, 8, 61, 255, 1000, 4093] {
            let ys: Vec<L::S> = (0..xs.len()).map(|i| xs[(i + stride) % xs.len()]).collect();
            for (px, py) in xs.chunks(L::N).zip(ys.chunks(L::N)) {
                let (mut bx, mut by) = ([L::S::ZERO; MAX_LANES], [L::S::ZERO; MAX_LANES]);
                bx[..px.len()].copy_from_slice(px);
                by[..py.len()].copy_from_slice(py);
                let mut got = [L::S::ZERO; MAX_LANES];
                L::load(k, &bx).max_exp(L::load(k, &by)).store(&mut got);
                for l in 0..px.len() {
                    let (x, y, g) = (px[l], py[l], got[l]);
                    let what =
                        format!("{} lanes, {:#x} and {:#x} gave {:#x}", L::N, x.bits(), y.bits(), g.bits());
                    assert_eq!(field(g), field(x).max(field(y)), "{what}");
                    assert_eq!(g.bits() >> (L::S::WIDTH - 1), 0, "sign set: {what}");
                    if L::MAX_EXP_EXACT && field(x) != L::S::EXP_MASK && field(y) != L::S::EXP_MASK {
                        let max = if x.bits() > y.bits() { x } else { y };
                        assert_eq!(g.bits(), max.bits(), "not the maximum: {what}");
                    }
                    checked += 1;
                }
            }
        }
        checked
    }

    /// `V3::unit_pow2` gives every lane its largest component in [1, 2) (0 stays 0), bit for
    /// bit the scalar answer, whatever the other lanes hold: finite samples of every exponent
    /// (subnormals among them, which take the second step) mixed across lanes.
    fn unit_pow2_is_lane_by_lane<L: Lanes>(k: L::K) -> usize
    where
        L::S: Lanes<S = L::S>,
    {
        let xs: Vec<L::S> =
            samples::<L::S>().into_iter().filter(|x| x.bits() & L::S::EXP_MASK != L::S::EXP_MASK).collect();
        let mut checked = 0;
        for stride in [1, 7, 97] {
            let comp = |i: usize, c: usize| xs[(i * stride + c) % xs.len()];
            for base in (0..xs.len()).step_by(L::N) {
                let mut buf = [[L::S::ZERO; MAX_LANES]; 3];
                for l in 0..L::N {
                    for (c, b) in buf.iter_mut().enumerate() {
                        b[l] = comp(base + l, c);
                    }
                }
                let v = V3::new(L::load(k, &buf[0]), L::load(k, &buf[1]), L::load(k, &buf[2])).unit_pow2();
                let mut got = [[L::S::ZERO; MAX_LANES]; 3];
                v.x.store(&mut got[0]);
                v.y.store(&mut got[1]);
                v.z.store(&mut got[2]);
                for l in 0..L::N {
                    let one = V3::new(buf[0][l], buf[1][l], buf[2][l]).unit_pow2();
                    let want = [one.x, one.y, one.z];
                    for c in 0..3 {
                        assert_eq!(got[c][l].bits(), want[c].bits(), "{} lanes, lane {l} of {base}", L::N);
                    }
                    let absb = |x: L::S| L::S::from_bits64(x.bits() & !(1u64 << (L::S::WIDTH - 1)));
                    let m = want.iter().fold(L::S::ZERO, |m, &x| if absb(x) > m { absb(x) } else { m });
                    let all_zero = [buf[0][l], buf[1][l], buf[2][l]].iter().all(|&x| absb(x) == L::S::ZERO);
                    assert!(
                        all_zero || (m >= L::S::ONE && m < L::S::from_f64(2.0)),
                        "{m:?} from lane {l} of {base}"
                    );
                    checked += 1;
                }
            }
        }
        checked
    }

    #[test]
    fn unit_pow2_scales_each_lane_on_its_own() {
        assert!(unit_pow2_is_lane_by_lane::<f32>(Portable) > 0);
        assert!(unit_pow2_is_lane_by_lane::<f64>(Portable) > 0);
        on_every_vector_type!(unit_pow2_is_lane_by_lane);
    }

    #[test]
    fn max_exp_takes_the_larger_exponent_on_every_lane_type() {
        assert_eq!(max_exp_takes_the_larger_exponent::<f32>(Portable), 8 * 256 * 4);
        assert_eq!(max_exp_takes_the_larger_exponent::<f64>(Portable), 8 * 2048 * 4);
        on_every_vector_type!(max_exp_takes_the_larger_exponent);
    }

    /// `clamp01` of every non-NaN sample (every exponent, both signs, zeros, infinities) is
    /// the clamp to [0, 1] bit for bit, `+0` for negatives and `-0`, lane by lane.
    fn clamp01_is_the_clamp<L: Lanes>(k: L::K) -> usize {
        let xs: Vec<L::S> = samples::<L::S>().into_iter().filter(|x| !x.is_nan()).collect();
        for part in xs.chunks(L::N) {
            let mut buf = [L::S::ZERO; MAX_LANES];
            buf[..part.len()].copy_from_slice(part);
            let mut got = [L::S::ZERO; MAX_LANES];
            L::load(k, &buf).clamp01().store(&mut got);
            for (l, &x) in part.iter().enumerate() {
                let want = if x > L::S::ZERO {
                    if x < L::S::ONE {
                        x
                    } else {
                        L::S::ONE
                    }
                } else {
                    L::S::ZERO
                };
                assert_eq!(got[l].bits(), want.bits(), "{} lanes, input {x:?}", L::N);
            }
        }
        xs.len()
    }

    #[test]
    fn clamp01_clamps_every_value_on_every_lane_type() {
        assert_eq!(clamp01_is_the_clamp::<f32>(Portable), 256 * 8 - 6);
        assert_eq!(clamp01_is_the_clamp::<f64>(Portable), 2048 * 8 - 6);
        on_every_vector_type!(clamp01_is_the_clamp);
    }

    #[test]
    fn recip_exponent_is_the_exact_reciprocal_on_every_lane_type() {
        assert_eq!(recip_exponent_is_exact::<f32>(Portable), 256 * 8);
        assert_eq!(recip_exponent_is_exact::<f64>(Portable), 2048 * 8);
        on_every_vector_type!(recip_exponent_is_exact);
    }
}
