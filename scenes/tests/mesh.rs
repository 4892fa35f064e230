//! The mesh queries against an exact brute force over all triangle pairs, on every family of
//! `mesh_scenes`, both precisions and every available instruction set.
//!
//! The reference moves the triangles exactly as the queries do ([`tridist::Mesh::triangle_at`],
//! the pose's rounding is the caller's input) and answers every pair with the exact oracle:
//! - distance: the excess `E = |d - d*| / (u S)` of the mesh distance over the exact minimum
//!   `d*` (S: the largest moved coordinate of both meshes), the reported pair's own exact
//!   distance, and the closest points lying on the reported triangles;
//! - contacts: every pair exactly within `margin - allow` is reported, none beyond
//!   `margin + allow` (`allow`: the verdict contract, 65 u S of the pair), each once;
//! - intersection: `Some` when some pair exactly intersects, and a reported pair is within
//!   `allow` of touching; `None` only when every pair is exactly apart by more than 0;
//! - closest point: as distance, for query points around the first mesh.

use rug::Rational;
use tridist::{Engine, Isa, Mesh, Pose, Real};
use tridist_oracle as oracle;
use tridist_scenes::mesh_scenes::{pose_in, scene, FAMILIES};
use tridist_scenes::rng::Rng;

/// Scenes per family and precision (blobs of 7 segments: 84 triangles, 7056 pairs).
const SCENES: u64 = 4;
const K: usize = 7;

/// The largest E measured over every family, precision and variant (2026-11-23, seed 1), and
/// the bound: measured x 1.25 + 0.25, as the triangle rows (scenes/src/measured.in).
const MEASURED_E: f64 = 1.498;
const BOUND_E: f64 = 2.2;

fn moved<T: Real>(m: &Mesh<T>, p: &Pose<T>) -> Vec<[[f64; 3]; 3]> {
    (0..m.len()).map(|i| m.triangle_at(i, p).map(|v| v.map(Real::to_f64))).collect()
}

fn exact_tri(t: &[[f64; 3]; 3]) -> [oracle::P3; 3] {
    oracle::exact_points(t).expect("finite")
}

fn mag(ts: &[[[f64; 3]; 3]]) -> f64 {
    ts.iter().flatten().flatten().fold(0.0f64, |m, x| m.max(x.abs()))
}

fn rat(x: f64) -> Rational {
    Rational::from_f64(x).expect("finite")
}

struct Worst {
    e: f64,
    what: String,
}

/// Checks the mesh queries of every available instruction set on scene `idx` of `fam` in
/// precision `T`; the exact reference is computed once.
fn check_scene<T: Real>(fam: &'static str, idx: u64, worst: &mut Worst) {
    let s = scene(fam, 1, idx, K);
    let (ma, mb) = (s.a.mesh::<T>(), s.b.mesh::<T>());
    let (pa, pb) = (pose_in::<T>(&s.pose_a), pose_in::<T>(&s.pose_b));
    let (ta, tb) = (moved(&ma, &pa), moved(&mb, &pb));
    let (ea, eb): (Vec<_>, Vec<_>) = (ta.iter().map(exact_tri).collect(), tb.iter().map(exact_tri).collect());
    let u = T::UNIT_ROUNDOFF.to_f64();
    let big_s = mag(&ta).max(mag(&tb));
    // all pairs, exactly
    let mut d2 = vec![vec![Rational::new(); eb.len()]; ea.len()];
    let mut best = None::<Rational>;
    let mut any_hit = false;
    for (i, x) in ea.iter().enumerate() {
        for (j, y) in eb.iter().enumerate() {
            let d = oracle::triangle_triangle(x, y).d2;
            any_hit |= d == 0;
            if best.as_ref().is_none_or(|b| &d < b) {
                best = Some(d.clone());
            }
            d2[i][j] = d;
        }
    }
    let best = best.expect("non-empty meshes");
    let dstar = best.to_f64().sqrt();
    let mut rng = Rng::new(idx);
    let points: Vec<([T; 3], Rational)> = (0..4)
        .map(|_| {
            let t = &ta[rng.below(ta.len())];
            let x = [0, 1, 2].map(|k| T::from_f64(t[0][k] + rng.range(-0.3, 0.3)));
            let xe = oracle::exact_point(&x.map(Real::to_f64)).expect("finite");
            (x, eb.iter().map(|t| oracle::point_triangle(&xe, t).d2).min().expect("non-empty"))
        })
        .collect();
    let mut note = |v: f64, what: &str, tag: &str| {
        if v > worst.e {
            *worst = Worst { e: v, what: format!("{tag} {what}") };
        }
        assert!(v <= BOUND_E, "{tag}: {what} E = {v} (bound {BOUND_E})");
    };
    for isa in Isa::ALL.into_iter().filter(|i| i.is_available()) {
        let e = Engine::new(isa).expect("available");
        let tag = format!("{fam}/{idx} {} {}", T::PRECISION.name(), e.isa());

        // 1. distance
        let r = e.mesh_distance(&ma, &pa, &mb, &pb).expect("valid input").expect("non-empty");
        let err = (r.sqdist.to_f64().sqrt() - dstar).abs() / (u * big_s);
        let pair = d2[r.tri_a][r.tri_b].to_f64().sqrt();
        let err_pair = (r.sqdist.to_f64().sqrt() - pair).abs() / (u * big_s);
        for (pt, t) in [(r.p, &ea[r.tri_a]), (r.q, &eb[r.tri_b])] {
            let x = oracle::exact_point(&pt.map(Real::to_f64)).expect("finite");
            note(
                oracle::point_triangle(&x, t).d2.to_f64().sqrt() / (u * big_s),
                "point off its triangle",
                &tag,
            );
        }
        note(err, "distance", &tag);
        note(err_pair, "reported pair", &tag);

        // 2. contacts at a margin just above the minimum and at 5 % of the size
        for margin in [dstar * 1.5 + 1e-3 * big_s.min(4.0), 0.05 * big_s.min(4.0)] {
            let m = T::from_f64(margin);
            let got = e.mesh_contacts(&ma, &pa, &mb, &pb, m, None).expect("valid");
            let mut seen = std::collections::HashSet::new();
            for c in &got {
                assert!(seen.insert((c.tri_a, c.tri_b)), "{tag}: pair {:?} twice", (c.tri_a, c.tri_b));
                assert!(c.sqdist.to_f64() <= m.to_f64() * m.to_f64(), "{tag}: contact beyond the margin");
            }
            for (i, row) in d2.iter().enumerate() {
                for (j, d) in row.iter().enumerate() {
                    let s = mag(&[ta[i], tb[j]]);
                    let allow = 65.0 * u * s;
                    let (lo, hi) = ((m.to_f64() - allow).max(0.0), m.to_f64() + allow);
                    if *d <= rat(lo) * rat(lo) {
                        assert!(
                            seen.contains(&(i, j)),
                            "{tag}: pair ({i}, {j}) at {} within margin {margin} missed",
                            d.to_f64().sqrt()
                        );
                    }
                    if *d > rat(hi) * rat(hi) {
                        assert!(
                            !seen.contains(&(i, j)),
                            "{tag}: pair ({i}, {j}) at {} beyond margin {margin} reported",
                            d.to_f64().sqrt()
                        );
                    }
                }
            }
            // a cap keeps the first of the order (distance, then triangle numbers)
            let capped = e.mesh_contacts(&ma, &pa, &mb, &pb, m, Some(3)).expect("valid");
            assert_eq!(capped[..], got[..got.len().min(3)], "{tag}");
            assert!(got
                .windows(2)
                .all(|w| (w[0].sqdist, w[0].tri_a, w[0].tri_b) <= (w[1].sqdist, w[1].tri_a, w[1].tri_b)));
        }

        // 3. intersection
        match e.mesh_intersect(&ma, &pa, &mb, &pb).expect("valid") {
            Some((i, j)) => {
                let allow = 65.0 * u * mag(&[ta[i], tb[j]]);
                assert!(
                    d2[i][j] <= rat(allow) * rat(allow),
                    "{tag}: pair ({i}, {j}) said intersecting at {}",
                    d2[i][j].to_f64().sqrt()
                );
            }
            None => assert!(!any_hit, "{tag}: intersecting meshes said apart"),
        }

        // 4. closest point of the second mesh to points around the first
        for (x, exact_min) in &points {
            let xe = oracle::exact_point(&x.map(Real::to_f64)).expect("finite");
            let r = e.mesh_closest_point(&mb, &pb, *x).expect("valid").expect("non-empty");
            let s = big_s.max(x.iter().fold(0.0f64, |m, c| m.max(c.to_f64().abs())));
            note(
                (r.sqdist.to_f64().sqrt() - exact_min.to_f64().sqrt()).abs() / (u * s),
                "closest point",
                &tag,
            );
            let own = oracle::point_triangle(&xe, &eb[r.tri]).d2.to_f64().sqrt();
            note((own - r.sqdist.to_f64().sqrt()).abs() / (u * s), "closest point's triangle", &tag);
        }
    }
}

#[test]
fn mesh_queries_against_exact_brute_force() {
    let mut worst = Worst { e: 0.0, what: String::new() };
    for fam in FAMILIES {
        for idx in 0..SCENES {
            check_scene::<f32>(fam, idx, &mut worst);
            check_scene::<f64>(fam, idx, &mut worst);
        }
    }
    println!("largest mesh E: {:.3} at {} (measured row: {MEASURED_E})", worst.e, worst.what);
}
