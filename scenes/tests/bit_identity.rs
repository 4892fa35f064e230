//! Scalar, SoA, SSE4.1 and AVX (no FMA) evaluate the same operations in the same order (one
//! algorithm over the `Lanes` trait, no fused multiply-add, no reassociation), so they must
//! give identical bits on every family: distance, closest points, certified interval and
//! verdict. AVX2+FMA differs by design (fused multiply-adds round once) and is held to the
//! bound table; AVX-512 runs the same fused operations as AVX2+FMA, on 16/8 lanes instead of
//! 8/4, so it must give AVX2+FMA's bits. The cheapest strong test there is: any ISA-specific
//! slip (a wrong shuffle, a mask of the wrong width, a lane-order mistake in the tail, a blend
//! with its operands swapped) breaks it on some pair.

use tridist::Query;
use tridist_scenes::eval::{run, Output, Variant};
use tridist_scenes::{families, Family, Float};

/// Groups of variants that evaluate the same operations in the same order: the first of each
/// is the reference.
const SAME_ORDER: [&[Variant]; 2] = [
    &[Variant::Scalar, Variant::Soa, Variant::Sse41, Variant::Avx],
    &[Variant::Avx2Fma, Variant::Avx512Vl, Variant::Avx512],
];

/// Bits of a value, with every NaN the same (payloads are not part of the contract).
fn bits<T: Float>(x: T) -> u64 {
    let x = x.to_f64();
    if x.is_nan() {
        u64::MAX
    } else {
        x.to_bits()
    }
}

fn fingerprint<T: Float>(o: &Output<T>, i: usize) -> Vec<u64> {
    let mut v = vec![bits(o.d[i]), bits(o.iv[i].lo), bits(o.iv[i].hi), o.verdict[i] as u64];
    for pt in [&o.p[i], &o.q[i]] {
        v.extend(pt.iter().map(|&c| bits(c)));
    }
    v
}

fn check<T: Float>(group: &[Variant]) {
    let mut compared = 0;
    if group[0].engine_or_skip().is_none() {
        eprintln!("bit_identity: {} unavailable on this CPU, group not compared", group[0].name());
        return;
    }
    for &q in Query::ALL {
        for family in Family::ALL {
            // a different seed from the differential test: more pairs seen overall
            let cases = families::generate::<T>(family, tridist_scenes::seed() ^ 0x5eed, 200);
            let margins: Vec<T> = cases.iter().map(|_| T::from_f64(0.05)).collect();
            let reference = run(q, group[0], &cases, Some(&margins)).expect("reference runs");
            for &v in group.iter().skip(1).filter(|v| v.engine_or_skip().is_some()) {
                let o = run(q, v, &cases, Some(&margins)).expect("variant runs");
                for i in 0..cases.len() {
                    assert_eq!(
                        fingerprint(&reference, i),
                        fingerprint(&o, i),
                        "{} {} {} {}: {} differs from {} on {}",
                        q.name(),
                        T::NAME,
                        family.name(),
                        i,
                        v.name(),
                        group[0].name(),
                        cases[i].label
                    );
                }
                compared += 1;
            }
        }
    }
    if group[1..].iter().any(|v| v.engine_or_skip().is_some()) {
        assert!(compared > 0, "nothing compared");
    } else {
        eprintln!("bit_identity: no variant of {group:?} to compare with {}", group[0].name());
    }
}

#[test]
fn same_order_variants_agree_bit_for_bit_f32() {
    check::<f32>(SAME_ORDER[0]);
}

#[test]
fn same_order_variants_agree_bit_for_bit_f64() {
    check::<f64>(SAME_ORDER[0]);
}

#[test]
fn fused_variants_agree_bit_for_bit_f32() {
    check::<f32>(SAME_ORDER[1]);
}

#[test]
fn fused_variants_agree_bit_for_bit_f64() {
    check::<f64>(SAME_ORDER[1]);
}
