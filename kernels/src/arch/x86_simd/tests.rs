use super::*;
use crate::lanes::Portable;
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
