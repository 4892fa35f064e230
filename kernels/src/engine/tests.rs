//! Unit tests of the engine: threads refused by the system, the documented default tolerance.

use super::threads::REFUSE_THREADS;
use super::*;
use std::sync::atomic::Ordering;

#[test]
fn a_system_out_of_threads_still_answers_every_pair() {
    // pairs of parallel triangles overlapping in plan, 13 heights apart: each distance exact
    let n = 3 * Engine::MIN_PARALLEL + 77;
    let tri = |z: f64, s: f64| [[0.0, 0.0, z], [s, 0.0, z], [0.0, s, z]];
    let a: Vec<_> = (0..n).map(|i| tri(0.0, 1.0 + (i % 7) as f64)).collect();
    let b: Vec<_> = (0..n).map(|i| tri(0.5 + (i % 13) as f64, 2.0)).collect();
    let mut one = vec![f64::NAN; n];
    Engine::auto().sqdist_triangle_triangle(&a, &b, &mut one).unwrap();
    REFUSE_THREADS.store(true, Ordering::Relaxed);
    let mut split = vec![f64::NAN; n];
    let r = Engine::auto().threads(3).sqdist_triangle_triangle(&a, &b, &mut split);
    REFUSE_THREADS.store(false, Ordering::Relaxed);
    r.unwrap();
    for i in 0..n {
        let dz = 0.5 + (i % 13) as f64;
        assert_eq!(one[i], dz * dz, "pair {i}");
        assert_eq!(split[i].to_bits(), one[i].to_bits(), "pair {i}");
    }
}

/// Every line of the crate's docs that states the default tolerance states the one
/// [`Tolerance::DEFAULT`] has (two lines said 32 where the code has 64).
#[test]
fn the_docs_state_the_default_tolerance() {
    let want = format!("`{} u S`", Tolerance::DEFAULT.scaled);
    let mut stated = 0;
    for (file, text) in [
        ("lib.rs", include_str!("../lib.rs")),
        ("single.rs", include_str!("../single.rs")),
        ("engine/mod.rs", include_str!("mod.rs")),
        ("engine/options.rs", include_str!("options.rs")),
    ] {
        for (n, line) in text.lines().enumerate() {
            if line.contains("default") && line.contains(" u S`") && line.trim_start().starts_with("//") {
                assert!(line.contains(&want), "{file}:{}: {line}", n + 1);
                stated += 1;
            }
        }
    }
    assert!(stated >= 3, "{stated} lines state the default");
}
