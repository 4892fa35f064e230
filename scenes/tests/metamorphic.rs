//! Metamorphic properties judged against the oracle: swapping the triangles and permuting each
//! triangle's vertices (all 36 combinations) must stay within the bound table; power-of-two
//! scaling must scale every variant's answer exactly (barring overflow and underflow).

use tridist::Query;
use tridist_scenes::bounds::violations;
use tridist_scenes::eval::{run, truth, Variant};
use tridist_scenes::{families, Case, Family, Float};

const PERMS: [[usize; 3]; 6] = [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]];

fn permuted<T: Float>(c: &Case<T>, pa: [usize; 3], pb: [usize; 3], swap: bool) -> Case<T> {
    let a = pa.map(|k| c.a[k]);
    let b = pb.map(|k| c.b[k]);
    let (a, b) = if swap { (b, a) } else { (a, b) };
    Case { label: format!("{}/perm{pa:?}{pb:?}/swap{swap}", c.label), a, b }
}

fn permutations_within_bounds<T: Float>() {
    for family in [
        Family::Random,
        Family::Degenerate,
        Family::Parallel,
        Family::NearParallel,
        Family::Touching,
        Family::NearMiss,
        Family::Intersecting,
    ] {
        let base = families::generate::<T>(family, tridist_scenes::seed() ^ 0x5eed, 12);
        let tr = truth(Query::TriTri, &base);
        for swap in [false, true] {
            for pa in PERMS {
                for pb in PERMS {
                    let cases: Vec<_> = base.iter().map(|c| permuted(c, pa, pb, swap)).collect();
                    for q in [Query::TriTri, Query::TriTriBrute, Query::Intersect] {
                        let bad = violations(q, Some(family), &cases, &tr);
                        assert!(bad.is_empty(), "perm {pa:?} {pb:?} swap {swap}:\n{}", bad.join("\n"));
                    }
                }
            }
        }
    }
}

#[test]
fn swaps_and_vertex_permutations_f32() {
    permutations_within_bounds::<f32>();
}

#[test]
fn swaps_and_vertex_permutations_f64() {
    permutations_within_bounds::<f64>();
}

#[test]
fn power_of_two_scaling_is_exact_on_every_family() {
    for family in Family::ALL {
        let base = families::generate::<f64>(family, tridist_scenes::seed(), 40);
        for k in [-40i32, -3, 5, 30] {
            let f = 2f64.powi(k);
            let scaled: Vec<_> = base
                .iter()
                .map(|c| Case {
                    label: c.label.clone(),
                    a: c.a.map(|p| p.map(|x| x * f)),
                    b: c.b.map(|p| p.map(|x| x * f)),
                })
                .collect();
            for v in Variant::ALL {
                if v.engine_or_skip().is_none() {
                    continue;
                }
                for q in [Query::TriTri, Query::TriTriBrute, Query::SegSeg, Query::PointTri] {
                    let o1 = run(q, v, &base, None).expect("an available variant runs");
                    let o2 = run(q, v, &scaled, None).expect("an available variant runs");
                    for i in 0..base.len() {
                        let want = o1.d[i] * f * f;
                        if want == 0.0 || (want.abs() >= f64::MIN_POSITIVE && want.is_finite()) {
                            assert_eq!(
                                o2.d[i].to_bits(),
                                want.to_bits(),
                                "{} {} {} 2^{k}: {}",
                                q.name(),
                                v.name(),
                                family.name(),
                                base[i].label
                            );
                        }
                    }
                }
            }
        }
    }
}
