//! Scalar, SoA, SSE4.1 and AVX (no FMA) evaluate the same operations in the same order (one
//! algorithm over the `Lanes` trait, no fused multiply-add, no reassociation), so they must
//! give identical bits on every family: distance, closest points, certified interval and
//! verdict. AVX2+FMA differs by design (fused multiply-adds round once) and is only held to
//! the bound table. The cheapest strong test there is: any ISA-specific slip (a wrong shuffle,
//! a mask of the wrong width, a lane-order mistake in the tail) breaks it on some pair.

use tridist::Query;
use tridist_scenes::eval::{run, Output, Variant};
use tridist_scenes::{families, Family, Float};

const SAME_ORDER: [Variant; 4] = [Variant::Scalar, Variant::Soa, Variant::Sse41, Variant::Avx];

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

fn check<T: Float>() {
    let mut compared = 0;
    for &q in Query::ALL {
        for family in Family::ALL {
            // a different seed from the differential test: more pairs seen overall
            let cases = families::generate::<T>(family, tridist_scenes::seed() ^ 0x5eed, 200);
            let margins: Vec<T> = cases.iter().map(|_| T::from_f64(0.05)).collect();
            let reference = run(q, Variant::Scalar, &cases, Some(&margins)).expect("scalar runs");
            for v in SAME_ORDER.into_iter().skip(1).filter(|v| v.available()) {
                let o = run(q, v, &cases, Some(&margins)).expect("variant runs");
                for i in 0..cases.len() {
                    assert_eq!(
                        fingerprint(&reference, i),
                        fingerprint(&o, i),
                        "{} {} {} {}: {} differs from scalar on {}",
                        q.name(),
                        T::NAME,
                        family.name(),
                        i,
                        v.name(),
                        cases[i].label
                    );
                }
                compared += 1;
            }
        }
    }
    assert!(compared > 0, "no SIMD variant available to compare");
}

#[test]
fn same_order_variants_agree_bit_for_bit_f32() {
    check::<f32>();
}

#[test]
fn same_order_variants_agree_bit_for_bit_f64() {
    check::<f64>();
}
