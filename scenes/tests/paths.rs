//! The certified pipeline's division of labour: on generic input the fast stage's own
//! certificate accepts (nearly) every pair, so the later stages stay the exception the
//! throughput report says they are. (The answers are judged elsewhere; a fast stage that
//! computed poor candidates would still give right answers through escalation, only slowly:
//! these tests catch that.)

use tridist::{Engine, Isa, Outputs, PathCounts, Query, Triangle};
use tridist_scenes::{families, Family};

type Pairs = Vec<(Triangle<f64>, Triangle<f64>)>;

fn counts<T: tridist::Real>(e: Engine, pairs: &Pairs) -> PathCounts {
    let c = |t: &Triangle<f64>| t.map(|p| p.map(T::from_f64));
    let a: Vec<_> = pairs.iter().map(|x| c(&x.0)).collect();
    let b: Vec<_> = pairs.iter().map(|x| c(&x.1)).collect();
    let mut d = vec![T::ZERO; a.len()];
    e.run(Query::TriTri, &a, &b, Outputs::new().sqdist(&mut d)).expect("valid input")
}

fn workloads() -> Vec<(&'static str, Pairs)> {
    let arm = tridist_scenes::mesh::carried("armadillo.off").expect("the carried Armadillo");
    let fam = |f| families::generate::<f64>(f, 11, 2000).into_iter().map(|c| (c.a, c.b)).collect();
    vec![
        ("random", fam(Family::Random)),
        ("near_parallel", fam(Family::NearParallel)),
        ("arm_nearby", tridist_scenes::protocol::nearby_pairs(&arm, 3.0, 2000, 7)),
    ]
}

/// Pairs that went beyond the fast stage (re-certified, recomputed, widened or exact).
fn beyond(c: &PathCounts) -> u64 {
    c.recertified + c.compacted + c.widened + c.exact
}

// Measured (2000 pairs each, every variant): the quick stage leaves 16 of the Armadillo's
// nearby pairs (0.8 %) to the full fast stage, 1471-1500 random pairs (74-75 %: a quarter
// intersect, and the front edges are not the closest pair of about half the others) and
// 1396-1419 (f32) / 830-855 (f64) near-parallel pairs (70-71 % / 42-43 %); after the full fast
// stage random pairs at most 26 re-certified (23 before a contact answer's witness points had
// to meet, 8811bc4), 2 recomputed and 1 widened (f32; 1.45 % in all, close under the 1.5 %
// bound), the Armadillo's none, the near-parallel family 36.3 % (f32) and 10.5 % (f64)
// re-certified and 0-2 recomputed (none before the tight certificate's allowance went from 8
// to 5 u S). (Before the full stage's answers had to be sharp, 6e9bb19:
// random 4 re-certified, near-parallel 28.6 % / 8.4 %: the rule sends the answers whose own
// arithmetic leaves them more than 8 u from their gap to the tight certificate, which accepts
// nearly all of them.) The bounds leave a small margin.
#[test]
fn the_fast_stage_certifies_generic_pairs() {
    for (name, pairs) in workloads() {
        let n = pairs.len() as u64;
        for isa in Isa::ALL {
            let Ok(e) = Engine::new(isa) else { continue };
            for (prec, c) in [("f32", counts::<f32>(e, &pairs)), ("f64", counts::<f64>(e, &pairs))] {
                let at = format!("{name} {isa:?} {prec}: {c:?}");
                assert_eq!(c.pairs, n, "{at}");
                assert_eq!(c.uncertified, 0, "{at}");
                match name {
                    "random" => {
                        assert!(c.refined * 100 <= 80 * n, "{at}");
                        assert!(beyond(&c) * 1000 <= 15 * n, "{at}");
                    }
                    "arm_nearby" => {
                        // the quick stage's front edges answer nearby mesh triangles
                        assert!(c.refined * 1000 <= 10 * n, "{at}");
                        assert!(beyond(&c) * 400 <= n, "{at}");
                    }
                    _ => {
                        // nearly parallel edges need the tight certificate, not the accurate stage
                        assert!((c.compacted + c.widened) * 400 <= n, "{at}");
                        let (refined, recert) = if prec == "f32" { (76, 38) } else { (48, 12) };
                        assert!(c.refined * 100 <= refined * n, "{at}");
                        assert!(c.recertified * 100 <= recert * n, "{at}");
                    }
                }
            }
        }
    }
}
