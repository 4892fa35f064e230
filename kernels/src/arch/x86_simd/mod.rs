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

use crate::isa::Isa;
use crate::lanes::Token;
use crate::lanes::{GatherIx, Lanes, Mask};

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
        Isa::Sse41.cpu_has().then_some(Sse41(()))
    }
}
#[cfg(feature = "avx")]
impl Avx {
    /// A token when this CPU has AVX (cached detection).
    pub(crate) fn detect() -> Option<Self> {
        Isa::Avx.cpu_has().then_some(Avx(()))
    }
}
impl Avx2Fma {
    /// A token when this CPU has AVX, AVX2 and FMA (cached detection).
    pub(crate) fn detect() -> Option<Self> {
        Isa::Avx2Fma.cpu_has().then_some(Avx2Fma(()))
    }
}
#[cfg(feature = "avx512vl")]
impl Avx512Vl {
    /// A token when this CPU has AVX-512F, AVX-512VL, AVX2 and FMA (cached detection).
    pub(crate) fn detect() -> Option<Self> {
        Isa::Avx512Vl.cpu_has().then_some(Avx512Vl(()))
    }
}
impl Avx512 {
    /// A token when this CPU has AVX-512F, AVX2 and FMA (cached detection).
    pub(crate) fn detect() -> Option<Self> {
        Isa::Avx512.cpu_has().then_some(Avx512(()))
    }
}

impl Token for Sse41 {}
#[cfg(feature = "avx")]
impl Token for Avx {}
impl Token for Avx2Fma {}
#[cfg(feature = "avx512vl")]
impl Token for Avx512Vl {}
impl Token for Avx512 {}

#[cfg(feature = "avx512vl")]
impl Avx512Vl {
    /// The AVX2+FMA token this one implies (detection requires AVX2 and FMA for AVX-512VL).
    #[cfg_attr(test, allow(dead_code))] // (its only callers, AVX-512VL's entry points, are not in the unit tests' build)
    pub(crate) fn avx2fma(self) -> Avx2Fma {
        Avx2Fma(())
    }
}

/// Tokens that prove SSE4.1 (the 128-bit types).
///
/// # Safety
/// A value of an implementing type may exist only where the CPU runs SSE4.1: the vector types
/// run its instructions on the strength of holding one.
pub(crate) unsafe trait HasSse41: Token {}
// SAFETY: `Sse41` is made only by `Sse41::detect`, after runtime detection found SSE4.1.
unsafe impl HasSse41 for Sse41 {}

/// Tokens that prove AVX (the 256-bit types); `FMA` when they also prove FMA.
///
/// # Safety
/// A value of an implementing type may exist only where the CPU runs AVX, and FMA, AVX2 and
/// AVX-512F with VL where the constants below say so: the vector types run those
/// instructions on the strength of holding one.
pub(crate) unsafe trait HasAvx: Token {
    const FMA: bool;
    /// Does the token also prove AVX2 (the 256-bit integer instructions)?
    const AVX2: bool;
    /// Does the token also prove AVX-512F and VL (the 256-bit register compress)?
    const VL: bool = false;
}
// SAFETY: `Avx` is made only by `Avx::detect`, after runtime detection found AVX; it claims
// neither FMA nor AVX2.
#[cfg(feature = "avx")]
unsafe impl HasAvx for Avx {
    const FMA: bool = false;
    const AVX2: bool = false;
}
// SAFETY: `Avx2Fma` is made only by `Avx2Fma::detect`, after runtime detection found AVX, AVX2
// and FMA.
unsafe impl HasAvx for Avx2Fma {
    const FMA: bool = true;
    const AVX2: bool = true;
}
// SAFETY: `Avx512Vl` is made only by `Avx512Vl::detect`, after runtime detection found AVX,
// AVX2, FMA, AVX-512F and AVX-512VL. (AVX-512VL's entry points are the 256-bit types with 32
// registers.)
#[cfg(feature = "avx512vl")]
unsafe impl HasAvx for Avx512Vl {
    const FMA: bool = true;
    const AVX2: bool = true;
    const VL: bool = true;
}
// SAFETY: `Avx512` is made only by `Avx512::detect`, after runtime detection found AVX, AVX2,
// FMA and AVX-512F; it does not claim VL. (The AVX-512 entry points run the mesh node test on
// the 256-bit types.)
unsafe impl HasAvx for Avx512 {
    const FMA: bool = true;
    const AVX2: bool = true;
}

/// Tokens that prove AVX-512F (the 512-bit types, always fused).
///
/// # Safety
/// A value of an implementing type may exist only where the CPU runs AVX-512F (with AVX2 and
/// FMA).
pub(crate) unsafe trait HasAvx512: Token {}
// SAFETY: `Avx512` is made only by `Avx512::detect`, after runtime detection found AVX-512F,
// AVX2 and FMA.
unsafe impl HasAvx512 for Avx512 {}

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
            if ix.top() >= col.len() || col.len() > i32::MAX as usize {
                return None;
            }
            // SAFETY: every offset is at most `ix.top()`, below `col.len()` (checked above),
            // and `ix.off()` holds them exactly as `col.len()` fits in i32 (`GatherIx::new`, its
            // fields private), so each lane reads an
            // element of `col`; `ix.off()` has at least the index vector's size; the first
            // argument is a token: detection found AVX-512F (module docs).
            Some(unsafe {
                let ix: $ix = $load_ix(ix.off().as_ptr().cast());
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

mod entries;
#[cfg(test)]
mod tests;
