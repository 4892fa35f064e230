//! ACCURACY.md's section on the correctly rounded mode: per family and precision, where the
//! pairs of triangle-triangle distance were decided under `Tolerance::CORRECTLY_ROUNDED`, and
//! every certified answer judged against the oracle's `RN(D*)` (and, asked for distances too,
//! `RN(sqrt(D*))`) bit for bit.

use std::fmt::Write;

use tridist::{Query, Tolerance};
use tridist_scenes::eval::{rn, rn_sqrt, run_with, run_with_distances, truth};
use tridist_scenes::{Family, Float};

/// One family and precision: pairs, decided by a proof of contact, by the oracle, undecided,
/// undecided when distances are asked for too, and certified but wrong (either run).
struct Row {
    family: Family,
    precision: &'static str,
    pairs: u64,
    contact: u64,
    exact: u64,
    undecided: u64,
    undecided_dist: u64,
    wrong: u64,
}

fn row<T: Float>(family: Family, seed: u64, n: usize) -> Option<Row> {
    let v = super::best();
    let e = v.engine().ok()?.tolerance(Tolerance::CORRECTLY_ROUNDED);
    let cases = tridist_scenes::families::generate::<T>(family, seed, n);
    let o = run_with(e, Query::TriTri, v, &cases, None).ok()?;
    let c = o.counts;
    let tr = truth(Query::TriTri, &cases);
    let od = run_with_distances(e, Query::TriTri, v, &cases, None).ok()?;
    let bits = |x: T| x.to_bits_u64();
    let wrong = (0..n)
        .filter(|&i| {
            let (sq, dist) = (rn::<T>(&tr[i].d2), rn_sqrt::<T>(&tr[i].d2));
            (o.certified[i] && bits(o.d[i]) != bits(sq))
                || (od.certified[i] && (bits(od.d[i]) != bits(sq) || bits(od.dist[i]) != bits(dist)))
        })
        .count() as u64;
    Some(Row {
        family,
        precision: T::NAME,
        pairs: c.pairs,
        contact: c.crossed,
        exact: c.exact,
        undecided: c.undecided,
        undecided_dist: od.counts.undecided,
        wrong,
    })
}

/// The section, on `n` cases per family and precision.
pub(super) fn rounded_md(n: usize, seed: u64) -> String {
    let mut a = String::new();
    let _ = writeln!(
        a,
        "\n## Correctly rounded answers\n\nTriangle-triangle distance under `Tolerance::CORRECTLY_ROUNDED` ({}, {n} cases per family and precision): every pair is answered in f64 (f32 input widened exactly) and decided when the squares of its certified interval round to one value; contacts by a proof (a shared point, or an edge crossing the other triangle's interior by orientation tests with a certified error bound): the f64 pass proves shared vertices and the crossing its fast stage names itself, with an exact interval (counted as decided), and *by a proof of contact* counts the per-pair proofs of what it leaves; the rest once more in f64 at `Tolerance::EXACT`, then by the exact oracle (feature `exact`, not in this build) or left *undecided* (flagged per pair, `Outputs::certified`). *Undecided with distances*: the same run asking for distances too (`Outputs::distances`, `RN(sqrt(D*))`, decided on its own from the same interval), where a pair is decided when both are: contacts not proven are the difference in f32, whose squares round to 0 while their distances need not. **Not RN**: certified answers whose bits differ from the oracle's correctly rounded square or distance, in either run (must be 0). Percent of the family's pairs; the time it costs: THROUGHPUT.md, \"The tolerance knob\".\n\n| family | prec | pairs | decided | by a proof of contact | by the oracle | undecided | undecided with distances | not RN |\n|---|---|---|---|---|---|---|---|---|",
        super::best().name()
    );
    for family in Family::ALL {
        for r in [row::<f32>(family, seed, n), row::<f64>(family, seed, n)].into_iter().flatten() {
            let _ = writeln!(
                a,
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                r.family.name(),
                r.precision,
                r.pairs,
                super::pct(r.pairs - r.undecided, r.pairs),
                super::pct(r.contact, r.pairs),
                super::pct(r.exact, r.pairs),
                super::pct(r.undecided, r.pairs),
                super::pct(r.undecided_dist, r.pairs),
                if r.wrong == 0 { "0".to_string() } else { format!("**{}**", r.wrong) }
            );
        }
    }
    a
}
