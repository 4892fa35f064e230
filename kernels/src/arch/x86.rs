//! x86-64 vector types: SSE4.1 (f32x4, f64x2) and AVX (f32x8, f64x4, with and without FMA).
//!
//! Soundness: values of these types are only created inside the `#[target_feature]` entry points
//! at the bottom of this file (every `Lanes` method is `#[inline(always)]` and is inlined into
//! them), and those entry points are only called by `crate::dispatch` after runtime feature
//! detection. The types are private to the crate, so no other code can create them.

use core::arch::x86_64::*;

use crate::driver::{run, Job};
use crate::lanes::{Lanes, Mask};

macro_rules! mask_type {
    ($name:ident, $reg:ty, $and:ident, $or:ident, $andnot:ident, $xor:ident, $movemask:ident, $full:expr, $feat:literal) => {
        #[derive(Clone, Copy)]
        pub(crate) struct $name($reg);
        impl Mask for $name {
            #[inline(always)]
            fn and(self, o: Self) -> Self {
                // SAFETY: only reached inside entry points with `$feat` enabled (module docs).
                Self(unsafe { $and(self.0, o.0) })
            }
            #[inline(always)]
            fn or(self, o: Self) -> Self {
                // SAFETY: only reached inside entry points with `$feat` enabled (module docs).
                Self(unsafe { $or(self.0, o.0) })
            }
            #[inline(always)]
            fn andnot(self, o: Self) -> Self {
                // SAFETY: only reached inside entry points with `$feat` enabled (module docs).
                Self(unsafe { $andnot(o.0, self.0) })
            }
            #[inline(always)]
            fn not(self) -> Self {
                // SAFETY: only reached inside entry points with `$feat` enabled (module docs).
                Self(unsafe { $xor(self.0, $movemask::ones()) })
            }
            #[inline(always)]
            fn all(self) -> bool {
                // SAFETY: only reached inside entry points with `$feat` enabled (module docs).
                unsafe { $movemask::mask(self.0) == $full }
            }
            #[inline(always)]
            fn any(self) -> bool {
                // SAFETY: only reached inside entry points with `$feat` enabled (module docs).
                unsafe { $movemask::mask(self.0) != 0 }
            }
        }
    };
}

/// Movemask and all-ones helpers per register type.
macro_rules! mm_helpers {
    ($name:ident, $reg:ty, $movemask:ident, $ones:expr) => {
        #[allow(non_camel_case_types)]
        struct $name;
        impl $name {
            #[inline(always)]
            unsafe fn mask(r: $reg) -> i32 {
                // SAFETY: the caller guarantees the CPU supports the instruction.
                unsafe { $movemask(r) }
            }
            #[inline(always)]
            fn ones() -> $reg {
                // SAFETY: only reached inside entry points with the feature enabled (module docs).
                unsafe { $ones }
            }
        }
    };
}

mm_helpers!(mm_ps, __m128, _mm_movemask_ps, _mm_castsi128_ps(_mm_set1_epi32(-1)));
mm_helpers!(mm_pd, __m128d, _mm_movemask_pd, _mm_castsi128_pd(_mm_set1_epi32(-1)));
mm_helpers!(mm256_ps, __m256, _mm256_movemask_ps, _mm256_castsi256_ps(_mm256_set1_epi32(-1)));
mm_helpers!(mm256_pd, __m256d, _mm256_movemask_pd, _mm256_castsi256_pd(_mm256_set1_epi32(-1)));

mask_type!(M32x4, __m128, _mm_and_ps, _mm_or_ps, _mm_andnot_ps, _mm_xor_ps, mm_ps, 0xf, "sse4.1");
mask_type!(M64x2, __m128d, _mm_and_pd, _mm_or_pd, _mm_andnot_pd, _mm_xor_pd, mm_pd, 0x3, "sse4.1");
mask_type!(
    M32x8,
    __m256,
    _mm256_and_ps,
    _mm256_or_ps,
    _mm256_andnot_ps,
    _mm256_xor_ps,
    mm256_ps,
    0xff,
    "avx"
);
mask_type!(
    M64x4,
    __m256d,
    _mm256_and_pd,
    _mm256_or_pd,
    _mm256_andnot_pd,
    _mm256_xor_pd,
    mm256_pd,
    0xf,
    "avx"
);

/// One vector type: `$fma` says whether `mul_add` is fused.
macro_rules! vec_type {
    (
        $name:ident, $s:ty, $n:expr, $reg:ty, $mask:ident, $feat:literal,
        set1 = $set1:ident, loadu = $loadu:ident, storeu = $storeu:ident,
        add = $add:ident, sub = $sub:ident, mul = $mul:ident, div = $div:ident,
        min = $min:ident, max = $max:ident, sqrt = $sqrt:ident, and = $and:ident,
        andnot = $andnot:ident, blendv = $blendv:ident, fmadd = $fmadd:ident,
        lt = $lt:expr, le = $le:expr, eq = $eq:expr, bits = $bits:ty
    ) => {
        #[derive(Clone, Copy)]
        pub(crate) struct $name<const FMA: bool>($reg);
        impl<const FMA: bool> Lanes for $name<FMA> {
            type S = $s;
            type M = $mask;
            const N: usize = $n;
            const FMA: bool = FMA;
            #[inline(always)]
            fn splat(s: $s) -> Self {
                // SAFETY: only reached inside entry points with `$feat` enabled (module docs).
                Self(unsafe { $set1(s) })
            }
            #[inline(always)]
            fn load(src: &[$s]) -> Self {
                let src = &src[..$n];
                // SAFETY: `src` has exactly N readable elements (checked by the slice above);
                // feature enabled as in the module docs.
                Self(unsafe { $loadu(src.as_ptr()) })
            }
            #[inline(always)]
            fn store(self, dst: &mut [$s]) {
                let dst = &mut dst[..$n];
                // SAFETY: `dst` has exactly N writable elements; feature as in the module docs.
                unsafe { $storeu(dst.as_mut_ptr(), self.0) }
            }
            #[inline(always)]
            fn add(self, o: Self) -> Self {
                // SAFETY: feature enabled in the calling entry point (module docs).
                Self(unsafe { $add(self.0, o.0) })
            }
            #[inline(always)]
            fn sub(self, o: Self) -> Self {
                // SAFETY: feature enabled in the calling entry point (module docs).
                Self(unsafe { $sub(self.0, o.0) })
            }
            #[inline(always)]
            fn mul(self, o: Self) -> Self {
                // SAFETY: feature enabled in the calling entry point (module docs).
                Self(unsafe { $mul(self.0, o.0) })
            }
            #[inline(always)]
            fn div(self, o: Self) -> Self {
                // SAFETY: feature enabled in the calling entry point (module docs).
                Self(unsafe { $div(self.0, o.0) })
            }
            #[inline(always)]
            fn mul_add(self, b: Self, c: Self) -> Self {
                if FMA {
                    // SAFETY: FMA = true is only instantiated by the avx2+fma entry points.
                    Self(unsafe { $fmadd(self.0, b.0, c.0) })
                } else {
                    self.mul(b).add(c)
                }
            }
            #[inline(always)]
            fn min(self, o: Self) -> Self {
                // SAFETY: feature enabled in the calling entry point (module docs).
                Self(unsafe { $min(self.0, o.0) })
            }
            #[inline(always)]
            fn max(self, o: Self) -> Self {
                // SAFETY: feature enabled in the calling entry point (module docs).
                Self(unsafe { $max(self.0, o.0) })
            }
            #[inline(always)]
            fn abs(self) -> Self {
                // SAFETY: feature enabled in the calling entry point (module docs).
                Self(unsafe { $andnot($set1(-0.0), self.0) })
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                // SAFETY: feature enabled in the calling entry point (module docs).
                Self(unsafe { $sqrt(self.0) })
            }
            #[inline(always)]
            fn lt(self, o: Self) -> $mask {
                // SAFETY: feature enabled in the calling entry point (module docs).
                $mask(unsafe { $lt(self.0, o.0) })
            }
            #[inline(always)]
            fn le(self, o: Self) -> $mask {
                // SAFETY: feature enabled in the calling entry point (module docs).
                $mask(unsafe { $le(self.0, o.0) })
            }
            #[inline(always)]
            fn eq(self, o: Self) -> $mask {
                // SAFETY: feature enabled in the calling entry point (module docs).
                $mask(unsafe { $eq(self.0, o.0) })
            }
            #[inline(always)]
            fn select(m: $mask, t: Self, f: Self) -> Self {
                // SAFETY: feature enabled in the calling entry point (module docs).
                Self(unsafe { $blendv(f.0, t.0, m.0) })
            }
            #[inline(always)]
            fn exponent(self) -> Self {
                let m = <$s>::from_bits(<$s as crate::real::Real>::EXP_MASK_BITS as $bits);
                // SAFETY: feature enabled in the calling entry point (module docs).
                Self(unsafe { $and(self.0, $set1(m)) })
            }
        }
    };
}

vec_type!(
    F32x4,
    f32,
    4,
    __m128,
    M32x4,
    "sse4.1",
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
    bits = u32
);
vec_type!(
    F64x2,
    f64,
    2,
    __m128d,
    M64x2,
    "sse4.1",
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
    bits = u64
);
vec_type!(
    F32x8,
    f32,
    8,
    __m256,
    M32x8,
    "avx",
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
    bits = u32
);
vec_type!(
    F64x4,
    f64,
    4,
    __m256d,
    M64x4,
    "avx",
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
    bits = u64
);

/// The `#[target_feature]` entry points: thin wrappers that instantiate the generic driver.
macro_rules! entry {
    ($name:ident, $t:ty, $lanes:ty, $feat:literal) => {
        /// # Safety
        /// The CPU must support the features named in `#[target_feature]`.
        #[target_feature(enable = $feat)]
        pub(crate) unsafe fn $name(job: &mut Job<'_, $t>) {
            run::<$lanes>(job)
        }
    };
}
entry!(sse41_f32, f32, F32x4<false>, "sse4.1");
entry!(sse41_f64, f64, F64x2<false>, "sse4.1");
entry!(avx_f32, f32, F32x8<false>, "avx");
entry!(avx_f64, f64, F64x4<false>, "avx");
entry!(avx2fma_f32, f32, F32x8<true>, "avx2,fma");
entry!(avx2fma_f64, f64, F64x4<true>, "avx2,fma");
