//! How often does a reduced candidate set hold the triangle-triangle answer? The measurement
//! behind the quick stage's choice (`kernels/src/algo/fast.rs`, `tri_tri_quick`): for nearby
//! Armadillo pairs and random unit-cube pairs, the share of pairs at positive distance whose
//! distance some candidate of each set reaches (to 1e-9 relative), and for the pairs at
//! distance 0 whether the front edges reach it.
//!
//! `cargo run --release -p tridist-scenes --example quick_probe [pairs]`
use tridist::{
    sqdist_point_triangle as pt, sqdist_segment_segment as ss, sqdist_triangle_triangle as tt, Triangle,
};

type Pairs = Vec<(Triangle<f64>, Triangle<f64>)>;

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The vertex indices of `t` ordered by projection on `c`, descending (the first triangle's
/// vertices towards the second) or ascending (the second's towards the first).
fn order(t: &Triangle<f64>, c: [f64; 3], descending: bool) -> [usize; 3] {
    let mut o = [0, 1, 2];
    o.sort_by(|&x, &y| {
        let (a, b) = (dot(c, t[x]), dot(c, t[y]));
        if descending {
            b.total_cmp(&a)
        } else {
            a.total_cmp(&b)
        }
    });
    o
}

/// The two edges at vertex `i` of `t`.
fn edges_at(t: &Triangle<f64>, i: usize) -> [[[f64; 3]; 2]; 2] {
    [[t[i], t[(i + 1) % 3]], [t[(i + 2) % 3], t[i]]]
}

const SETS: [&str; 6] = [
    "front edge pair (the quick stage)",
    "  + the foremost vertices over the other face",
    "closest vertex pair: its 4 edge pairs",
    "  + its 2 vertex-face",
    "all 9 edge pairs",
    "all 15 features",
];

fn main() {
    let n: usize = std::env::args().nth(1).and_then(|x| x.parse().ok()).unwrap_or(20_000);
    let arm = tridist_scenes::mesh::carried("armadillo.off").expect("the carried Armadillo");
    let random = tridist_scenes::families::generate::<f64>(tridist_scenes::Family::Random, 7, n);
    let workloads: [(&str, Pairs); 2] = [
        ("arm_nearby", tridist_scenes::protocol::nearby_pairs(&arm, 3.0, n, 7)),
        ("random", random.into_iter().map(|c| (c.a, c.b)).collect()),
    ];
    for (name, pairs) in workloads {
        let (mut hits, mut apart) = ([0usize; SETS.len()], 0usize);
        let (mut zero, mut zero_front) = (0usize, 0usize);
        for (s, t) in &pairs {
            let d = tt(s, t);
            let cs = [0, 1, 2].map(|k| (s[0][k] + s[1][k] + s[2][k]) / 3.0);
            let ct = [0, 1, 2].map(|k| (t[0][k] + t[1][k] + t[2][k]) / 3.0);
            let c = sub(ct, cs);
            let (os, ot) = (order(s, c, true), order(t, c, false));
            let front = ss(&[s[os[0]], s[os[1]]], &[t[ot[0]], t[ot[1]]]);
            if d == 0.0 {
                zero += 1;
                zero_front += usize::from(front == 0.0);
                continue;
            }
            apart += 1;
            let reaches = |x: f64| x <= d * (1.0 + 1e-9);
            let foremost = pt(&s[os[0]], t).min(pt(&t[ot[0]], s));
            let (mut bi, mut bj, mut bd) = (0, 0, f64::INFINITY);
            for i in 0..3 {
                for j in 0..3 {
                    let v = sub(t[j], s[i]);
                    if dot(v, v) < bd {
                        (bi, bj, bd) = (i, j, dot(v, v));
                    }
                }
            }
            let mut four = f64::INFINITY;
            for a in edges_at(s, bi) {
                for b in edges_at(t, bj) {
                    four = four.min(ss(&a, &b));
                }
            }
            let closest_vf = pt(&s[bi], t).min(pt(&t[bj], s));
            let mut nine = f64::INFINITY;
            for i in 0..3 {
                for j in 0..3 {
                    nine = nine.min(ss(&[s[i], s[(i + 1) % 3]], &[t[j], t[(j + 1) % 3]]));
                }
            }
            let all_vf = (0..3).map(|k| pt(&s[k], t).min(pt(&t[k], s))).fold(f64::INFINITY, f64::min);
            let sets = [front, front.min(foremost), four, four.min(closest_vf), nine, nine.min(all_vf)];
            for (h, x) in hits.iter_mut().zip(sets) {
                *h += usize::from(reaches(x));
            }
        }
        println!(
            "{name}: {} pairs; {zero} at distance 0, of which the front edge pair reaches 0 for {zero_front}; of the {apart} others, reached by:",
            pairs.len()
        );
        for (label, h) in SETS.iter().zip(hits) {
            println!("  {label}: {:.2} %", 100.0 * h as f64 / apart.max(1) as f64);
        }
    }
}
