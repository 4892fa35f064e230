//! The lane-generic vector trait every algorithm is written against, its 1-lane scalar
//! implementation, and a small 3-vector of lanes.
//!
//! Algorithms in [`crate::algo`] are written once over [`Lanes`]; the ISA layer
//! ([`crate::arch`]) only supplies the vector types and the `#[target_feature]` entry points.
//!
//! Soundness: a lane type names a capability token ([`Lanes::K`]) and every way to make a
//! value from nothing ([`Lanes::splat`], [`Lanes::load`]) takes one. A token of an instruction
//! set exists only if runtime detection found it (`crate::isa`), and every vector value carries
//! its token (a zero-sized field), so any value of a SIMD lane type proves that the CPU runs its
//! instructions: the vector methods are safe to call from anywhere in the crate. Inlined into a
//! `#[target_feature]` entry point they compile to single instructions; called from elsewhere
//! they would be slow, never undefined.

use crate::real::Real;

/// The most lanes of any vector type (AVX-512's f32x16): the size of the driver's lane buffers
/// and of the batch columns' padding.
pub(crate) const MAX_LANES: usize = 16;

/// The lane indices of one [`Lanes::gather`] group, prepared once for all its columns: the
/// indices, their largest, and (for the hardware gathers) as 32-bit offsets, valid when the
/// column's length fits in `i32` (then every index below it does). The fields are private:
/// [`GatherIx::new`] is the only way to make one, so `top` is the largest index and `off` the
/// indices exactly wherever they fit in `i32`, which the AVX-512 hardware gather's bounds
/// proof rests on (`crate::arch::x86_simd`).
pub(crate) struct GatherIx {
    at: [usize; MAX_LANES],
    off: [i32; MAX_LANES],
    top: usize,
}

impl GatherIx {
    #[inline(always)]
    pub(crate) fn new(at: [usize; MAX_LANES]) -> Self {
        let mut off = [0i32; MAX_LANES];
        for (o, &i) in off.iter_mut().zip(&at) {
            *o = i as i32;
        }
        GatherIx { at, off, top: at.iter().fold(0, |m, &i| m.max(i)) }
    }

    /// The lane indices.
    #[inline(always)]
    pub(crate) fn at(&self) -> &[usize; MAX_LANES] {
        &self.at
    }

    /// The lane indices as 32-bit offsets (exact where they fit in `i32`).
    #[inline(always)]
    pub(crate) fn off(&self) -> &[i32; MAX_LANES] {
        &self.off
    }

    /// The largest lane index.
    #[inline(always)]
    pub(crate) fn top(&self) -> usize {
        self.top
    }
}

/// [`Lanes::gather`] one lane at a time, through a buffer.
#[inline(always)]
pub(crate) fn gather_lanes<L: Lanes>(k: L::K, col: &[L::S], ix: &GatherIx) -> L {
    let mut buf = L::ZEROS;
    for (slot, &i) in buf.as_mut().iter_mut().zip(ix.at()) {
        *slot = col[i];
    }
    L::load(k, buf.as_ref())
}

/// [`Lanes::compress`] one lane at a time, through a buffer.
#[inline(always)]
pub(crate) fn compress_lanes<L: Lanes>(v: L, m: u32, dst: &mut [L::S]) {
    let mut buf = L::ZEROS;
    v.store(buf.as_mut());
    let dst = &mut dst[..L::N];
    let (mut rest, mut at) = (m, 0);
    while rest != 0 {
        dst[at] = buf.as_ref()[rest.trailing_zeros() as usize];
        at += 1;
        rest &= rest - 1;
    }
}

/// A lane mask: the result of a comparison, one boolean per lane.
pub(crate) trait Mask: Copy {
    fn and(self, o: Self) -> Self;
    fn or(self, o: Self) -> Self;
    /// `self & !o`.
    fn andnot(self, o: Self) -> Self;
    fn not(self) -> Self;
    fn all(self) -> bool;
    fn any(self) -> bool;
    /// One bit per lane, lane 0 in bit 0.
    fn bits(self) -> u32;
    #[inline(always)]
    #[allow(dead_code)]
    fn none(self) -> bool {
        !self.any()
    }
}

/// A capability token: a value exists only if this CPU runs the token's instruction set (the
/// SIMD tokens, in `crate::arch::x86_simd`, have private fields and are made only by runtime
/// detection). A lane type names its token, and every way to make a vector from nothing takes
/// one. The entry points of an instruction set are methods of its token
/// (`crate::arch::dispatch::Entries`).
pub(crate) trait Token: Copy + 'static {}

/// The token of the portable (scalar) variant: always available.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Portable;

impl Token for Portable {}

/// A vector of `N` lanes of one precision. Every method is `#[inline(always)]` and carries no
/// target feature: the per-ISA entry point that instantiates an algorithm enables the features.
pub(crate) trait Lanes: Copy {
    type S: Real;
    type M: Mask;
    /// The capability token of the instruction set (see the module docs).
    type K: Token;
    const N: usize;
    /// `N` values of the precision: a lane buffer exactly as long as the vector, so that
    /// storing a vector fills it and the optimiser drops its zeroing. (A buffer of
    /// [`MAX_LANES`] kept a 640-byte `memset` call in every group of the batch driver's
    /// output path: `callgrind` of `spin tri_tri arm_nearby f32 avx2fma 0.3 4000 1 points`.)
    type Arr: Copy + AsRef<[Self::S]> + AsMut<[Self::S]>;
    /// An [`Lanes::Arr`] of zeros.
    const ZEROS: Self::Arr;
    /// Is `mul_add` fused (one rounding)?
    const FMA: bool;
    /// The token this value carries.
    fn token(self) -> Self::K;
    fn splat(k: Self::K, s: Self::S) -> Self;
    /// Loads the first `N` values of `src` (panics if `src` is shorter).
    fn load(k: Self::K, src: &[Self::S]) -> Self;
    /// Stores into the first `N` values of `dst` (panics if `dst` is shorter).
    fn store(self, dst: &mut [Self::S]);
    fn add(self, o: Self) -> Self;
    fn sub(self, o: Self) -> Self;
    fn mul(self, o: Self) -> Self;
    fn div(self, o: Self) -> Self;
    /// `self * b + c`, fused only in the FMA variants.
    fn mul_add(self, b: Self, c: Self) -> Self;
    /// Minimum; returns `o` when either is NaN (SSE semantics).
    fn min(self, o: Self) -> Self;
    /// Maximum; returns `o` when either is NaN (SSE semantics).
    fn max(self, o: Self) -> Self;
    fn abs(self) -> Self;
    #[allow(dead_code)]
    fn sqrt(self) -> Self;
    fn lt(self, o: Self) -> Self::M;
    fn le(self, o: Self) -> Self::M;
    #[allow(dead_code)]
    fn eq(self, o: Self) -> Self::M;
    /// `m ? t : f` per lane.
    fn select(m: Self::M, t: Self, f: Self) -> Self;
    /// Keeps only the exponent bits: the largest power of two not above a positive normal value.
    fn exponent(self) -> Self;
    /// `1 / self.exponent()`, bit for bit for every input (0 and subnormals give +inf, inf
    /// and NaN give 0), without a division: for an exponent field `E`, its complement
    /// `255 - E` (`2047 - E` for f64; `!self & EXP_MASK`) is the field of `2 / 2^(E - bias)`,
    /// halved exactly by the multiplication (to a subnormal `2^-127` / `2^-1023` for the
    /// largest exponent). A division sat on the path of every scaling to a power of two (the
    /// prescaling, [`V3::unit_pow2`] twice per candidate): without the five of the quick
    /// stage, and with one bounds check per group of loads, `spin tri_tri arm_nearby f32
    /// avx2fma` went from 91-98 to 98-101 M/s (a971abd).
    fn recip_exponent(self) -> Self;
    /// For non-negative `self` and `o` (sign bits clear, as [`Lanes::abs`] leaves them): a
    /// non-negative value whose exponent field is the larger of theirs, all ones (inf or NaN)
    /// when either's is; its other bits are unspecified. An integer maximum of the bit
    /// patterns, where the hardware has one (SSE4.1 and AVX2: of each 32-bit half, whose high
    /// half holds an f64's exponent; AVX-512 and scalar: of the whole pattern), a one-cycle
    /// instruction where the floating-point maximum takes four. [`crate::algo::prescale`]
    /// reduces a pair's 18 coordinates with it to find their power of two and finiteness, on
    /// the path in front of every lane's arithmetic.
    fn max_exp(self, o: Self) -> Self;
    /// Is [`Lanes::max_exp`] of finite operands their maximum itself (an integer maximum of
    /// the whole bit patterns, or the floating-point maximum)? Then [`crate::algo::prescale`]
    /// takes the magnitude from the same tree.
    const MAX_EXP_EXACT: bool;
    /// `col[ix.at[l]]` in lane `l` (panics when an index is out of bounds): lane compaction. One
    /// load per lane through a buffer here; the AVX-512 types use the hardware gather. (AVX2's
    /// gather was tried for the 256-bit types: it halved the compacted stage's throughput on
    /// the AMD EPYC reference machine, `spin tri_tri random f32 avx2fma 2`.)
    #[inline(always)]
    fn gather(k: Self::K, col: &[Self::S], ix: &GatherIx) -> Self {
        gather_lanes(k, col, ix)
    }
    /// Has the hardware a register compress ([`Lanes::compress`] in one instruction:
    /// AVX-512's `vcompressps`/`vcompresspd`, also on 256-bit vectors with AVX-512VL)? Then the
    /// batch driver packs the quick stage's open pairs from its registers instead of gathering
    /// them (`crate::drv::Packed`). Without it the lane-by-lane form below is not used there:
    /// on AVX2+FMA it was no faster than the gather (`spin tri_tri random|arm_nearby f32|f64
    /// avx2fma 1`, Zen 5, three rounds: random f64 10.7-11.0 against 11.9-12.4 M/s).
    const COMPRESS: bool = false;
    /// Writes the lanes whose bit is set in `m` to the front of `dst`, in lane order, and
    /// `N` values in all (those beyond the packed ones unspecified; panics if `dst` is
    /// shorter than `N`).
    #[inline(always)]
    fn compress(self, m: u32, dst: &mut [Self::S]) {
        compress_lanes(self, m, dst)
    }

    #[inline(always)]
    fn gt(self, o: Self) -> Self::M {
        o.lt(self)
    }
    #[inline(always)]
    fn ge(self, o: Self) -> Self::M {
        o.le(self)
    }
    /// `s` in every lane, with `self`'s token.
    #[inline(always)]
    fn like(self, s: Self::S) -> Self {
        Self::splat(self.token(), s)
    }
    #[inline(always)]
    fn clamp01(self) -> Self {
        // max first: NaN never reaches here for finite input (divisions are guarded).
        self.max(self.like(Self::S::ZERO)).min(self.like(Self::S::ONE))
    }
    #[inline(always)]
    fn neg(self) -> Self {
        self.like(Self::S::ZERO).sub(self)
    }
    /// `self * b - c * d` with about one rounding error relative to the result, even under
    /// cancellation: Kahan's algorithm with a fused multiply-add, Dekker's exact products
    /// otherwise. Inputs must be prescaled (|x| well below sqrt(MAX)).
    #[inline(always)]
    fn diff_prod(self, b: Self, c: Self, d: Self) -> Self {
        if Self::FMA {
            let w = c.mul(d);
            let e = c.neg().mul_add(d, w); // w - c*d exactly
            let f = self.mul_add(b, w.neg()); // a*b - w, one rounding
            f.add(e)
        } else {
            let (p, ep) = two_prod(self, b);
            let (q, eq) = two_prod(c, d);
            // p - q is exact when it cancels (Sterbenz); the error terms are tiny.
            p.sub(q).add(ep.sub(eq))
        }
    }
    /// Knuth's TwoSum: `s + e == self + o` exactly (round to nearest, no overflow).
    #[inline(always)]
    fn two_sum(self, o: Self) -> (Self, Self) {
        let s = self.add(o);
        let bb = s.sub(self);
        let e = self.sub(s.sub(bb)).add(o.sub(bb));
        (s, e)
    }
    /// TwoProduct: `p + e == self * o` exactly (unless `e` underflows): one fused multiply-add,
    /// Dekker's product without FMA.
    #[inline(always)]
    fn two_prod(self, o: Self) -> (Self, Self) {
        if Self::FMA {
            let p = self.mul(o);
            (p, self.mul_add(o, p.neg()))
        } else {
            two_prod(self, o)
        }
    }
    /// `self / max(d, MIN_POSITIVE)` for a divisor that is mathematically non-negative: never
    /// 0/0, and a divisor that rounded below zero is treated as tiny.
    #[inline(always)]
    fn safe_div(self, d: Self) -> Self {
        self.div(d.max(self.like(Self::S::MIN_POSITIVE)))
    }
}

/// Dekker's exact product without FMA: `a*b = p + e` exactly (Veltkamp splitting).
#[inline(always)]
fn two_prod<L: Lanes>(a: L, b: L) -> (L, L) {
    // 2^ceil(p/2) + 1: 4097 for f32, 134217729 for f64.
    let split = a.like(L::S::from_f64(match L::S::PRECISION {
        crate::Precision::F32 => 4097.0,
        crate::Precision::F64 => 134_217_729.0,
    }));
    let p = a.mul(b);
    let (ah, al) = halves(a, split);
    let (bh, bl) = halves(b, split);
    let e = ah.mul(bh).sub(p).add(ah.mul(bl)).add(al.mul(bh)).add(al.mul(bl));
    (p, e)
}

/// Veltkamp splitting: `x = hi + lo` with both halves of at most half the precision.
#[inline(always)]
fn halves<L: Lanes>(x: L, split: L) -> (L, L) {
    let c = split.mul(x);
    let hi = c.sub(c.sub(x));
    (hi, x.sub(hi))
}

impl Mask for bool {
    #[inline(always)]
    fn and(self, o: Self) -> Self {
        self & o
    }
    #[inline(always)]
    fn or(self, o: Self) -> Self {
        self | o
    }
    #[inline(always)]
    fn andnot(self, o: Self) -> Self {
        self & !o
    }
    #[inline(always)]
    fn not(self) -> Self {
        !self
    }
    #[inline(always)]
    fn all(self) -> bool {
        self
    }
    #[inline(always)]
    fn any(self) -> bool {
        self
    }
    #[inline(always)]
    fn bits(self) -> u32 {
        self as u32
    }
}

macro_rules! scalar_lanes {
    ($t:ty) => {
        impl Lanes for $t {
            type S = $t;
            type M = bool;
            type K = Portable;
            const N: usize = 1;
            type Arr = [$t; 1];
            const ZEROS: [$t; 1] = [0.0];
            const FMA: bool = false;
            #[inline(always)]
            fn token(self) -> Self::K {
                Portable
            }
            #[inline(always)]
            fn splat(_: Self::K, s: $t) -> Self {
                s
            }
            #[inline(always)]
            fn load(_: Self::K, src: &[$t]) -> Self {
                src[0]
            }
            #[inline(always)]
            fn store(self, dst: &mut [$t]) {
                dst[0] = self;
            }
            #[inline(always)]
            fn add(self, o: Self) -> Self {
                self + o
            }
            #[inline(always)]
            fn sub(self, o: Self) -> Self {
                self - o
            }
            #[inline(always)]
            fn mul(self, o: Self) -> Self {
                self * o
            }
            #[inline(always)]
            fn div(self, o: Self) -> Self {
                self / o
            }
            #[inline(always)]
            fn mul_add(self, b: Self, c: Self) -> Self {
                // Never fused: the scalar variants are the unfused reference.
                self * b + c
            }
            #[inline(always)]
            fn min(self, o: Self) -> Self {
                if self < o {
                    self
                } else {
                    o
                }
            }
            #[inline(always)]
            fn max(self, o: Self) -> Self {
                if self > o {
                    self
                } else {
                    o
                }
            }
            #[inline(always)]
            fn abs(self) -> Self {
                <$t>::abs(self)
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            #[inline(always)]
            fn lt(self, o: Self) -> bool {
                self < o
            }
            #[inline(always)]
            fn le(self, o: Self) -> bool {
                self <= o
            }
            #[inline(always)]
            fn eq(self, o: Self) -> bool {
                self == o
            }
            #[inline(always)]
            fn select(m: bool, t: Self, f: Self) -> Self {
                if m {
                    t
                } else {
                    f
                }
            }
            #[inline(always)]
            fn exponent(self) -> Self {
                use crate::real::sealed::Sealed;
                <$t>::from_bits64(self.bits() & <$t>::EXP_MASK)
            }
            #[inline(always)]
            fn recip_exponent(self) -> Self {
                use crate::real::sealed::Sealed;
                <$t>::from_bits64(!self.bits() & <$t>::EXP_MASK) * 0.5
            }
            const MAX_EXP_EXACT: bool = true;
            #[inline(always)]
            fn max_exp(self, o: Self) -> Self {
                use crate::real::sealed::Sealed;
                <$t>::from_bits64(self.bits().max(o.bits()))
            }
        }
    };
}
scalar_lanes!(f32);
scalar_lanes!(f64);

/// A 3-vector whose components are lane vectors.
#[derive(Clone, Copy)]
pub(crate) struct V3<L> {
    pub x: L,
    pub y: L,
    pub z: L,
}

impl<L: Lanes> V3<L> {
    #[inline(always)]
    pub(crate) fn new(x: L, y: L, z: L) -> Self {
        V3 { x, y, z }
    }
    #[inline(always)]
    pub(crate) fn splat(x: L) -> Self {
        V3::new(x, x, x)
    }
    #[inline(always)]
    pub(crate) fn sub(self, o: Self) -> Self {
        V3::new(self.x.sub(o.x), self.y.sub(o.y), self.z.sub(o.z))
    }
    #[inline(always)]
    pub(crate) fn add(self, o: Self) -> Self {
        V3::new(self.x.add(o.x), self.y.add(o.y), self.z.add(o.z))
    }
    #[inline(always)]
    pub(crate) fn neg(self) -> Self {
        V3::new(self.x.neg(), self.y.neg(), self.z.neg())
    }
    #[inline(always)]
    pub(crate) fn scale(self, s: L) -> Self {
        V3::new(self.x.mul(s), self.y.mul(s), self.z.mul(s))
    }
    /// `self + d * s`, fused where the variant fuses.
    #[inline(always)]
    pub(crate) fn add_scaled(self, d: Self, s: L) -> Self {
        V3::new(d.x.mul_add(s, self.x), d.y.mul_add(s, self.y), d.z.mul_add(s, self.z))
    }
    #[inline(always)]
    pub(crate) fn dot(self, o: Self) -> L {
        self.x.mul_add(o.x, self.y.mul_add(o.y, self.z.mul(o.z)))
    }
    #[inline(always)]
    pub(crate) fn norm2(self) -> L {
        self.dot(self)
    }
    /// `|self|^2 + m`, `m` the smallest normal number, rounded as [`V3::dot`] rounds: never
    /// below `|self|^2 (1 - 3u)` though squares underflow (each then off by at most half the
    /// smallest subnormal, `m u`), so its square root bounds `|self|` for certificates at
    /// every magnitude, exceeding it by at most `sqrt(m)` (2^-63 for `f32`). The same
    /// operations as [`V3::norm2`], `m` added by the first product's multiply-add; the same
    /// bits unless `|self|^2 < m / u`.
    #[inline(always)]
    pub(crate) fn norm2_up(self) -> L {
        let m = Cx::of(self.x).splat(L::S::MIN_POSITIVE);
        self.x.mul_add(self.x, self.y.mul_add(self.y, self.z.mul_add(self.z, m)))
    }
    #[inline(always)]
    pub(crate) fn cross(self, o: Self) -> Self {
        V3::new(
            self.y.mul(o.z).sub(self.z.mul(o.y)),
            self.z.mul(o.x).sub(self.x.mul(o.z)),
            self.x.mul(o.y).sub(self.y.mul(o.x)),
        )
    }
    /// Cross product with every component computed by [`Lanes::diff_prod`]: accurate even
    /// for nearly parallel vectors.
    #[inline(always)]
    pub(crate) fn cross_accurate(self, o: Self) -> Self {
        V3::new(
            self.y.diff_prod(o.z, self.z, o.y),
            self.z.diff_prod(o.x, self.x, o.z),
            self.x.diff_prod(o.y, self.y, o.x),
        )
    }
    /// Sum of absolute components (an upper bound on the Euclidean norm).
    #[inline(always)]
    pub(crate) fn norm1(self) -> L {
        self.x.abs().add(self.y.abs()).add(self.z.abs())
    }
    /// Largest absolute component.
    #[inline(always)]
    pub(crate) fn norm_inf(self) -> L {
        self.x.abs().max(self.y.abs()).max(self.z.abs())
    }
    /// The same direction scaled by a power of two (exactly) so that its largest component is
    /// in [1, 2); 0 stays 0. Used as a projection direction, its norm cannot underflow or
    /// overflow (a direction built from products of small differences can).
    #[inline(always)]
    pub(crate) fn unit_pow2(self) -> Self {
        let k = Cx::of(self.x);
        let tiny = k.splat(L::S::MIN_POSITIVE);
        // 1/m, m the largest component's power of two, is exact; m >= MIN_POSITIVE keeps it
        // finite, and a subnormal direction scaled by 2^126 (2^1022) is exact too. Only the
        // largest exponent is read, so it is found by [`Lanes::max_exp`] (the candidates'
        // directions are on the quick stage's critical path).
        let m = self.max_exp();
        let v = self.scale(m.max_exp(tiny).recip_exponent());
        // A second step for subnormal input (1/MIN_POSITIVE alone leaves it below 1), taken
        // only when a lane needs it: it scales a lane already in [1, 2) by exactly 1, so a
        // lane's bits do not depend on its neighbours, and the usual case keeps it off the
        // path of the candidates' directions (the quick stage's critical path).
        // (0 stays 0 without it)
        if m.lt(tiny).and(m.gt(k.zero())).any() {
            v.scale(v.max_exp().max_exp(tiny).recip_exponent())
        } else {
            v
        }
    }
    /// A value with the exponent field of the largest absolute component ([`Lanes::max_exp`]).
    #[inline(always)]
    fn max_exp(self) -> L {
        self.x.abs().max_exp(self.y.abs()).max_exp(self.z.abs())
    }
    #[inline(always)]
    pub(crate) fn select(m: L::M, t: Self, f: Self) -> Self {
        V3::new(L::select(m, t.x, f.x), L::select(m, t.y, f.y), L::select(m, t.z, f.z))
    }
}

/// Constants of a lane type, made with a token taken from a value already in hand (see the
/// module docs): `let k = Cx::of(x); k.c(2.0)`.
#[derive(Clone, Copy)]
pub(crate) struct Cx<L: Lanes>(pub L::K);

impl<L: Lanes> Cx<L> {
    /// The token of `x`.
    #[inline(always)]
    pub(crate) fn of(x: L) -> Self {
        Cx(x.token())
    }
    #[inline(always)]
    pub(crate) fn splat(self, s: L::S) -> L {
        L::splat(self.0, s)
    }
    /// A constant given in f64 (rounded to the precision).
    #[inline(always)]
    pub(crate) fn c(self, x: f64) -> L {
        self.splat(L::S::from_f64(x))
    }
    #[inline(always)]
    pub(crate) fn zero(self) -> L {
        self.splat(L::S::ZERO)
    }
    #[inline(always)]
    pub(crate) fn one(self) -> L {
        self.splat(L::S::ONE)
    }
    /// The unit roundoff.
    #[inline(always)]
    pub(crate) fn u(self) -> L {
        self.splat(L::S::UNIT_ROUNDOFF)
    }
    #[inline(always)]
    pub(crate) fn inf(self) -> L {
        self.splat(L::S::INFINITY)
    }
    #[inline(always)]
    pub(crate) fn nan(self) -> L {
        self.splat(L::S::NAN)
    }
    /// All lanes true.
    #[inline(always)]
    pub(crate) fn yes(self) -> L::M {
        self.zero().le(self.zero())
    }
    /// All lanes false.
    #[inline(always)]
    pub(crate) fn no(self) -> L::M {
        self.zero().lt(self.zero())
    }
    #[inline(always)]
    pub(crate) fn v0(self) -> V3<L> {
        V3::splat(self.zero())
    }
}
