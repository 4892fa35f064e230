//! Shared pieces of the fuzz targets: a structured pair input whose modes reach the hard
//! configurations, and the differential check of every variant and precision against the oracle
//! and the bound table.

use arbitrary::Arbitrary;
use tridist::{Real, Triangle};
use tridist_scenes::bounds::violations;
use tridist_scenes::eval::{truth, Query};
use tridist_scenes::families::ulp_step;
use tridist_scenes::{Case, Family};

/// Fuzzer-chosen construction of a triangle pair.
#[derive(Arbitrary, Debug, Clone)]
pub struct PairInput {
    mode: u8,
    coords: [i16; 18],
    picks: [u8; 4],
    nudges: [i8; 4],
    scale_exp: i8,
    offset: i16,
}

/// The family whose bound row judges a mode.
fn family_of(mode: u8) -> Family {
    match mode % 8 {
        1 | 2 => Family::Touching,
        3 => Family::Parallel,
        4 => Family::Parallel,
        5 => Family::Touching,
        6 => Family::NearParallel,
        7 => Family::Degenerate,
        _ => Family::Random,
    }
}

impl PairInput {
    /// Builds the pair in precision T (None when scaling left the finite range).
    pub fn build<T: Real>(&self) -> Option<(Case<T>, Family)> {
        let c = |k: usize| self.coords[k] as f64 / 256.0;
        let p = |k: usize| [c(3 * k), c(3 * k + 1), c(3 * k + 2)];
        let mut a = [p(0), p(1), p(2)];
        let mut b = [p(3), p(4), p(5)];
        let pick = |k: usize| self.picks[k] as usize % 3;
        match self.mode % 8 {
            1 => b[0] = a[pick(0)], // shared vertex
            2 => {
                b[0] = a[pick(0)]; // shared edge
                b[1] = a[(pick(0) + 1) % 3];
            }
            3 => {
                for v in a.iter_mut().chain(b.iter_mut()) {
                    // coplanar
                    v[2] = c(0);
                }
            }
            4 => b = a.map(|v| [v[0] + c(9), v[1] + c(10), v[2] + c(11)]), // parallel translate
            5 => {
                // vertex of b on a's face (dyadic barycentrics: exact in f64)
                let (u, w) = ((self.picks[1] % 64) as f64 / 256.0, (self.picks[2] % 64) as f64 / 256.0);
                b[0] = [0, 1, 2].map(|k| a[0][k] + u * (a[1][k] - a[0][k]) + w * (a[2][k] - a[0][k]));
            }
            6 => {
                // b's first edge nearly parallel to a's first edge
                let d = [0, 1, 2].map(|k| a[1][k] - a[0][k]);
                b[1] = [0, 1, 2].map(|k| b[0][k] + d[k] + c(12 + k) * 1e-6);
            }
            7 => a[2] = a[pick(1)], // degenerate (repeated vertex)
            _ => {}
        }
        let f = 2f64.powi((self.scale_exp as i32).clamp(-60, 60));
        let off = self.offset as f64 * 64.0;
        let conv = |t: &[[f64; 3]; 3]| -> Triangle<T> { t.map(|v| v.map(|x| T::from_f64(x * f + off))) };
        let (mut ta, mut tb) = (conv(&a), conv(&b));
        for k in 0..4 {
            let idx = self.picks[k] as usize % 18;
            let t = if idx < 9 { &mut ta } else { &mut tb };
            let (v, cc) = ((idx % 9) / 3, idx % 3);
            t[v][cc] = ulp_step(t[v][cc], self.nudges[k] as i32 % 8);
        }
        let finite = ta.iter().chain(tb.iter()).flatten().all(|x| x.is_finite());
        finite.then(|| {
            (
                Case {
                    label: format!("{}/fuzz/mode{}", family_of(self.mode).name(), self.mode % 8),
                    a: ta,
                    b: tb,
                },
                family_of(self.mode),
            )
        })
    }
}

/// Runs `query` on every available variant for the case and panics, with a reproducible
/// description, when the bound table is exceeded or a contact is misclassified.
pub fn check<T: Real>(query: Query, case: Case<T>, family: Family) {
    let cases = vec![case];
    let bad = violations(query, family, &cases, &truth(query, &cases));
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// The differential check of one query in both precisions.
pub fn differential(input: &PairInput, query: Query) {
    if let Some((c, f)) = input.build::<f32>() {
        check(query, c, f);
    }
    if let Some((c, f)) = input.build::<f64>() {
        check(query, c, f);
    }
}
