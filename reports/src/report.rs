//! `tridist report`: the accuracy sweep, the throughput measurement (with the peers on the same
//! pairs in the same run), the path and tolerance breakdowns and the plots, written to
//! `reports/` and summarised in the README between the results markers.

use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::time::Duration;

use tridist::{Engine, PathCounts, Query, Tolerance};
use tridist_scenes::bounds::{bound, meets};
use tridist_scenes::eval::{run_with, summarise, sweep_family, truth, Row, Stats, Variant};
use tridist_scenes::float::Float;
use tridist_scenes::peer::{self, Lib, Peer};
use tridist_scenes::protocol::{self, Named};
use tridist_scenes::workload::{measure, measure_points, Workload};
use tridist_scenes::{families, Family};

use crate::common::{fmt, header, Progress};
use crate::plot::{Mark, Plot, Series};
use crate::table::{self, TRow};

mod readme;
mod rounded;
use readme::update_readme;

/// Report settings.
pub struct Settings {
    /// Cases per (query, family, precision).
    pub cases: usize,
    /// Pairs per throughput workload.
    pub pairs: usize,
    /// Time budget per throughput measurement.
    pub budget: Duration,
    /// Poses of the mesh trajectory.
    pub mesh_poses: usize,
    /// Largest subdivision level of the mesh report's scale section.
    pub mesh_scale: u32,
    /// The command line to print in headers.
    pub command: String,
    /// Where to write.
    pub out_dir: PathBuf,
    /// README to update (between the results markers), if any.
    pub readme: Option<PathBuf>,
}

/// A peer's accuracy on one family and precision.
struct PeerAcc {
    lib: Lib,
    family: Family,
    precision: &'static str,
    stats: Stats,
}

/// A peer's agreement with tridist on a workload (largest |d - d'| / S, pairs beyond 1e-3).
struct Agreement {
    workload: &'static str,
    lib: Lib,
    precision: &'static str,
    check: Result<(f64, usize), String>,
}

/// Everything measured.
struct Measured {
    acc: Vec<Row>,
    peer_acc: Vec<PeerAcc>,
    thr: Vec<TRow>,
    agree: Vec<Agreement>,
    failed: Vec<String>,
    workloads: Vec<(&'static str, &'static str)>,
    /// One and two threads measured alternately ([`threads_alternated`]).
    threads: Vec<ThreadRow>,
}

/// Triangle-triangle on one and on two threads, the same batch, measured alternately.
struct ThreadRow {
    workload: &'static str,
    precision: &'static str,
    pairs: usize,
    one: f64,
    two: f64,
    /// Two threads each running the whole batch on its own one-thread engine: what two
    /// independent workers reach together on this machine at that moment (the ceiling).
    apart: f64,
}

/// Batch size of the threads table's large row (the workload's pairs repeated).
const LARGE_BATCH: usize = 65_536;

/// Median queries/s of the best variant on one thread, on two threads, and of two independent
/// one-thread workers together ([`apart`]), measured alternately (three rounds, so the
/// machine's drift falls on all alike); `None` when a measurement fails.
fn threads_alternated<T: Peer>(w: &Workload<T>, e: Engine, budget: std::time::Duration) -> Option<[f64; 3]> {
    let mut r = [Vec::new(), Vec::new(), Vec::new()];
    for _ in 0..3 {
        r[0].push(measure(w, Query::TriTri, best(), Some(e.threads(1)), budget)?.ok()?.qps);
        r[1].push(measure(w, Query::TriTri, best(), Some(e.threads(2)), budget)?.ok()?.qps);
        r[2].push(apart(w, e.threads(1), budget)?);
    }
    Some(r.map(crate::common::median))
}

/// Queries/s of two threads each answering the whole batch over and over on `e` for `budget`,
/// together ([`crate::common::two_workers`]).
fn apart<T: Peer>(w: &Workload<T>, e: Engine, budget: std::time::Duration) -> Option<f64> {
    let n = w.len(Query::TriTri);
    let calls = crate::common::two_workers(
        budget,
        || (vec![T::ZERO; n], vec![tridist::Intersection::Invalid; n]),
        |(out, flags)| w.run(Query::TriTri, e, false, out, flags).is_ok(),
    )?;
    Some(calls * n as f64)
}

const TOLERANCES: [(&str, Tolerance); 6] = [
    ("correctly-rounded", Tolerance::CORRECTLY_ROUNDED),
    ("exact", Tolerance::EXACT),
    ("scaled:8", Tolerance::scaled(8.0)),
    ("default", Tolerance::DEFAULT),
    ("scaled:1024", Tolerance::scaled(1024.0)),
    ("abs:1e-3", Tolerance::absolute(1e-3)),
];

/// The variants the peer comparisons show: AVX2+FMA (the variant the speed targets name), and
/// the best one of this CPU when that is another (AVX-512).
fn shown_variants(best: &str) -> Vec<&str> {
    if best != "avx2fma" && Variant::Avx2Fma.available() {
        vec!["avx2fma", best]
    } else {
        vec![best]
    }
}

fn best() -> Variant {
    Variant::from_isa(tridist::Isa::best())
}

fn accuracy(s: &Settings, prog: &mut Progress) -> (Vec<Row>, Vec<PeerAcc>) {
    let seed = tridist_scenes::seed();
    let mut rows = Vec::new();
    for &q in Query::ALL {
        for f in Family::ALL {
            rows.extend(sweep_family::<f32>(q, f, seed, s.cases, |_, _| {}));
            rows.extend(sweep_family::<f64>(q, f, seed, s.cases, |_, _| {}));
            prog.step(&format!("accuracy {} {}", q.name(), f.name()));
        }
    }
    let mut peers = Vec::new();
    for lib in Lib::ALL.into_iter().filter(|l| l.available()) {
        for family in Family::ALL {
            peers.push(PeerAcc {
                lib,
                family,
                precision: "f32",
                stats: peer::judge::<f32>(lib, family, seed, s.cases),
            });
            peers.push(PeerAcc {
                lib,
                family,
                precision: "f64",
                stats: peer::judge::<f64>(lib, family, seed, s.cases),
            });
            prog.step(&format!("accuracy {} {}", lib.name(), family.name()));
        }
    }
    (rows, peers)
}

fn queries_of(id: &str) -> Vec<Query> {
    if id == "random" || id == "arm_nearby" {
        Query::ALL.to_vec()
    } else {
        vec![Query::PointTri, Query::SegSeg, Query::TriTri, Query::Within]
    }
}

/// Every query x variant on one workload and precision, then the thread, tolerance and peer
/// rows of the triangle-distance query.
fn throughput_one<T: Peer>(s: &Settings, wl: &Named, m: &mut Measured, prog: &mut Progress) {
    let w = Workload::<T>::new(&wl.pairs, 0.02);
    // (FCL's triangle distance always computes closest points; the other peer's and our own
    // rows write the answer alone unless `points` says so)
    // (`full`: without the quick stage; peers have no stages)
    let row_out = |q: Query,
                   imp: &str,
                   threads: usize,
                   tol: &str,
                   (points, full): (bool, bool),
                   r: tridist_scenes::workload::Measured| TRow {
        workload: wl.id.into(),
        query: q.name().into(),
        implementation: imp.into(),
        precision: T::NAME.into(),
        threads,
        tolerance: tol.into(),
        outputs: if points || imp == Lib::Fcl.name() { table::POINTS } else { table::ANSWER }.into(),
        stages: if is_peer(imp) {
            "-"
        } else if full {
            table::FULL
        } else {
            table::QUICK
        }
        .into(),
        qps: r.qps,
        counts: r.counts,
    };
    let row =
        |q: Query, imp: &str, threads: usize, tol: &str, r| row_out(q, imp, threads, tol, (false, false), r);
    for q in queries_of(wl.id) {
        for v in Variant::ALL {
            match measure(&w, q, v, None, s.budget) {
                None => {}
                Some(Ok(r)) => m.thr.push(row(q, v.name(), 1, "default", r)),
                Some(Err(e)) => {
                    m.failed.push(format!("{} {} {} {}: {e}", wl.id, q.name(), v.name(), T::NAME))
                }
            }
        }
        prog.step(&format!("throughput {} {} {}", wl.id, q.name(), T::NAME));
    }
    if wl.id != "random" && wl.id != "arm_nearby" {
        return;
    }
    let v = best();
    let Ok(e) = Engine::new(v.isa()) else { return };
    if let Some(Ok(r)) = measure(&w, Query::TriTri, v, Some(e.threads(2)), s.budget) {
        m.thr.push(row(Query::TriTri, v.name(), 2, "default", r));
    }
    let large: Vec<_> = wl.pairs.iter().cycle().take(LARGE_BATCH.max(wl.pairs.len())).copied().collect();
    let large = Workload::<T>::new(&large, 0.02);
    for w in [&w, &large] {
        if let Some([one, two, apart]) = threads_alternated(w, e, s.budget) {
            let pairs = w.len(Query::TriTri);
            m.threads.push(ThreadRow { workload: wl.id, precision: T::NAME, pairs, one, two, apart });
        }
    }
    for (name, tol) in TOLERANCES {
        if name == "default" {
            continue;
        }
        let et = e.tolerance(tol);
        if let Some(Ok(r)) = measure(&w, Query::TriTri, v, Some(et), s.budget) {
            m.thr.push(row(Query::TriTri, v.name(), 1, name, r));
        }
    }
    // with closest points, like for like with FCL, for the variants the comparison shows
    let shown = shown_variants(v.name());
    for x in Variant::ALL.into_iter().filter(|x| shown.contains(&x.name())) {
        match measure_points(&w, Query::TriTri, x, s.budget) {
            None => {}
            Some(Ok(r)) => m.thr.push(row_out(Query::TriTri, x.name(), 1, "default", (true, false), r)),
            Some(Err(e)) => {
                m.failed.push(format!("{} tri_tri {} {} with points: {e}", wl.id, x.name(), T::NAME))
            }
        }
        // and without the quick stage (`Engine::quick_stage(false)`), the answer alone
        let full = Engine::new(x.isa()).ok().map(|e| e.quick_stage(false));
        match full.and_then(|e| measure(&w, Query::TriTri, x, Some(e), s.budget)) {
            None => {}
            Some(Ok(r)) => m.thr.push(row_out(Query::TriTri, x.name(), 1, "default", (false, true), r)),
            Some(Err(e)) => m.failed.push(format!(
                "{} tri_tri {} {} without the quick stage: {e}",
                wl.id,
                x.name(),
                T::NAME
            )),
        }
    }
    let (a, b) = w.triangles();
    for lib in Lib::ALL.into_iter().filter(|l| l.available()) {
        // Timed whatever the agreement: the check catches harness errors (it passes on random
        // pairs for every peer, see the list in THROUGHPUT.md); where a peer disagrees on nearby
        // pairs that is its accuracy (ACCURACY.md), and the report says so beside its speed.
        let check = peer::agreement(lib, a, b);
        let secs = peer::time_pass(&peer::Shapes::for_lib(lib, a, b), s.budget);
        let r =
            tridist_scenes::workload::Measured { qps: a.len() as f64 / secs, counts: PathCounts::default() };
        m.thr.push(row(Query::TriTri, lib.name(), 1, "-", r));
        m.agree.push(Agreement { workload: wl.id, lib, precision: T::NAME, check });
    }
    prog.step(&format!("threads, tolerances, peers {} {}", wl.id, T::NAME));
}

fn throughput(s: &Settings, m: &mut Measured, prog: &mut Progress) -> Result<(), String> {
    for wl in protocol::standard(s.pairs, tridist_scenes::seed())? {
        m.workloads.push((wl.id, wl.title));
        throughput_one::<f32>(s, &wl, m, prog);
        throughput_one::<f64>(s, &wl, m, prog);
    }
    Ok(())
}

/// Per-case (S, E) of triangle-triangle on `family` for one variant.
fn per_case<T: Float>(family: Family, v: Variant, n: usize) -> Vec<(f64, f64)> {
    let cases = families::generate::<T>(family, tridist_scenes::seed() ^ 0xface, n);
    let tr = truth(Query::TriTri, &cases);
    let Ok(out) = v.engine().and_then(|e| run_with(e, Query::TriTri, v, &cases, None)) else {
        return Vec::new();
    };
    let (_, js) = summarise(Query::TriTri, &cases, &tr, &out, 0.0, None);
    js.iter().zip(&tr).map(|(j, t)| (t.s, j.excess)).collect()
}

/// Max over decade bins of x (E below 1e-3 drawn at 1e-3).
fn binned(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut m: BTreeMap<i64, f64> = BTreeMap::new();
    for &(x, y) in points {
        if x > 0.0 && y.is_finite() {
            let e = m.entry(x.log10().floor() as i64).or_insert(0.0);
            *e = e.max(y);
        }
    }
    m.into_iter().map(|(k, y)| (10f64.powi(k as i32) * 3.16, y.max(1e-3))).collect()
}

fn stability(family: Family, n: usize) -> Vec<Series> {
    let mut out = Vec::new();
    for (i, v) in [Variant::Scalar, best()].into_iter().enumerate() {
        out.push(Series::line(format!("{} f32", v.name()), 2 * i, binned(&per_case::<f32>(family, v, n))));
        out.push(Series::line(
            format!("{} f64", v.name()),
            2 * i + 1,
            binned(&per_case::<f64>(family, v, n)),
        ));
    }
    out
}

/// One row of the penalty sweep.
struct PenaltyRow {
    max_iter: u32,
    median: f64,
    p99: f64,
    max: f64,
    qps: f64,
}

/// The penalty method on random unit-cube pairs with tolerance 0 (every pair runs exactly
/// `max_iter` steps).
fn penalty_sweep<T: Float>(v: Variant, n: usize) -> Vec<PenaltyRow> {
    let cases = families::generate::<T>(Family::Random, tridist_scenes::seed(), n);
    let tr = truth(Query::Penalty, &cases);
    let mut out = Vec::new();
    for it in [1u32, 2, 3, 4, 6, 8, 16, 32] {
        let opts = tridist::PenaltyOptions {
            tol: T::MIN_POSITIVE,
            max_iter: it,
            ..tridist::PenaltyOptions::default()
        };
        let Ok(e) = v.engine().map(|e| e.penalty(&opts)) else { continue };
        let t0 = std::time::Instant::now();
        let Ok(o) = run_with(e, Query::Penalty, v, &cases, None) else { continue };
        let secs = t0.elapsed().as_secs_f64().max(1e-9);
        let (st, _) = summarise(Query::Penalty, &cases, &tr, &o, 0.0, None);
        out.push(PenaltyRow {
            max_iter: it,
            median: st.median,
            p99: st.p99,
            max: st.max_excess,
            qps: n as f64 / secs,
        });
    }
    out
}

fn write_file(dir: &Path, name: &str, text: &str) -> Result<(), String> {
    std::fs::write(dir.join(name), text).map_err(|e| format!("{}: {e}", dir.join(name).display()))
}

/// Lookup of a throughput figure (default tolerance unless named; the answer alone, or
/// closest points too when `points`: a peer has one row, whatever it computes; the default
/// engine, or without the quick stage when `full`).
#[allow(clippy::too_many_arguments)]
fn qps_of(
    t: &[TRow],
    wl: &str,
    q: Query,
    imp: &str,
    p: &str,
    threads: usize,
    tol: &str,
    (points, full): (bool, bool),
) -> Option<f64> {
    let peer = is_peer(imp);
    t.iter()
        .find(|r| {
            r.workload == wl
                && r.query == q.name()
                && r.implementation == imp
                && r.precision == p
                && r.threads == threads
                && r.tolerance == tol
                && (peer || r.answer_only() != points)
                && r.full_stages() == full
        })
        .map(|r| r.qps)
}

/// One thread, default tolerance, the answer alone, without the quick stage.
fn q1_full(t: &[TRow], wl: &str, imp: &str, p: &str) -> Option<f64> {
    qps_of(t, wl, Query::TriTri, imp, p, 1, "default", (false, true))
}

/// [`qps_of`] of the answer alone.
fn qps(t: &[TRow], wl: &str, q: Query, imp: &str, p: &str, threads: usize, tol: &str) -> Option<f64> {
    qps_of(t, wl, q, imp, p, threads, tol, (false, false))
}

/// Is `imp` a peer library (its rows have no tolerance, and one output set)?
fn is_peer(imp: &str) -> bool {
    Lib::ALL.iter().any(|l| l.name() == imp)
}

fn q1(t: &[TRow], wl: &str, q: Query, imp: &str, p: &str) -> Option<f64> {
    let tol = if is_peer(imp) { "-" } else { "default" };
    qps(t, wl, q, imp, p, 1, tol)
}

/// One thread, default tolerance, with closest points.
fn q1_points(t: &[TRow], wl: &str, imp: &str, p: &str) -> Option<f64> {
    qps_of(t, wl, Query::TriTri, imp, p, 1, "default", (true, false))
}

fn mq(x: Option<f64>) -> String {
    x.map(|v| format!("{:.2}", v / 1e6)).unwrap_or_else(|| "-".into())
}

fn ratio(a: Option<f64>, b: Option<f64>) -> String {
    match (a, b) {
        (Some(x), Some(y)) if y > 0.0 => format!("{:.2}x", x / y),
        _ => "-".into(),
    }
}

fn pct(n: u64, of: u64) -> String {
    if of == 0 {
        "-".into()
    } else {
        let p = 100.0 * n as f64 / of as f64;
        if n == 0 {
            "0".into()
        } else if p < 0.01 {
            format!("{p:.1e}%")
        } else {
            format!("{p:.2}%")
        }
    }
}

fn misclassified(s: &Stats) -> usize {
    s.contact_misses + s.false_zeros + s.nonfinite
}

/// Runs the whole report.
pub fn run_report(s: &Settings) -> Result<(), String> {
    std::fs::create_dir_all(&s.out_dir).map_err(|e| format!("{}: {e}", s.out_dir.display()))?;
    let seed = tridist_scenes::seed();
    let peers = Lib::ALL.iter().filter(|l| l.available()).count();
    let steps = Query::ALL.len() * Family::ALL.len()
        + peers * Family::ALL.len()
        + 2 * (2 * Query::ALL.len() + 4 * 4 + 2)
        + 4
        + 2;
    let mut prog = Progress::new(steps);
    let (acc, peer_acc) = accuracy(s, &mut prog);
    let mut m = Measured {
        acc,
        peer_acc,
        thr: Vec::new(),
        agree: Vec::new(),
        failed: Vec::new(),
        workloads: Vec::new(),
        threads: Vec::new(),
    };
    throughput(s, &mut m, &mut prog)?;
    let mag = stability(Family::Scale, s.cases * 2);
    prog.step("stability: magnitude");
    let off = stability(Family::Far, s.cases * 2);
    prog.step("stability: offset");
    let pen32 = penalty_sweep::<f32>(best(), s.cases * 2);
    let pen64 = penalty_sweep::<f64>(best(), s.cases * 2);
    prog.step("penalty sweep");

    write_file(&s.out_dir, "ACCURACY.md", &accuracy_md(s, seed, &m))?;
    write_file(&s.out_dir, "THROUGHPUT.md", &throughput_md(s, seed, &m))?;
    table::write(&s.out_dir.join("throughput.csv"), &m.thr)?;
    write_file(&s.out_dir, "tradeoff.svg", &tradeoff_plot(&m).render()?)?;
    let stab = |title: &str, xl: &str, series| Plot {
        title: title.into(),
        xlabel: xl.into(),
        ylabel: "max excess E per decade".into(),
        series,
        hline: Some((bound_target(), "target E = 8".into())),
    };
    write_file(
        &s.out_dir,
        "magnitude.svg",
        &stab("Stability vs magnitude (tri-tri, scale family)", "largest coordinate S", mag).render()?,
    )?;
    write_file(
        &s.out_dir,
        "offset.svg",
        &stab("Stability vs offset from origin (tri-tri, far family)", "offset (largest coordinate S)", off)
            .render()?,
    )?;
    write_file(&s.out_dir, "penalty.svg", &penalty_plot(&pen32, &pen64).render()?)?;
    write_file(&s.out_dir, "TRADEOFF.md", &tradeoff_md(s, seed, &m, &pen32, &pen64))?;
    let (mesh, mesh_summary) = crate::meshreport::mesh_md(s, seed)?;
    write_file(&s.out_dir, "MESH.md", &mesh)?;
    prog.step("writing reports");
    if let Some(readme) = &s.readme {
        update_readme(readme, &m, &mesh_summary)?;
    }
    prog.step("README results");
    if !m.failed.is_empty() {
        return Err(format!("{} throughput result check(s) failed; see THROUGHPUT.md", m.failed.len()));
    }
    Ok(())
}

fn bound_target() -> f64 {
    tridist_scenes::bounds::TARGET
}

fn accuracy_md(s: &Settings, seed: u64, m: &Measured) -> String {
    let acc = &m.acc;
    let mut a = header("Accuracy of every kernel variant against the exact oracle", &s.command, seed);
    let _ = writeln!(
        a,
        "Metrics as defined in [docs/ACCURACY.md](../docs/ACCURACY.md). **E** = |sqrt(D^) - d*| / (u S), reported as the *excess* over the correctly rounded exact answer; ULP error of the squared distance where D* >= (2^10 u S)^2; contact misses (D* = 0 reported above 8 u S); false zeros beyond 8 u S (and, strictly, any positive D* reported as 0); non-finite outputs for finite input; closest-point error (offset of a returned point from its primitive, or |p - q| against d*, scaled like E). **Interval misses**: certified intervals [lo, hi] that do not contain the exact distance, or answers that are not the square of a distance in [lo, hi] rounded once (must be 0). **Width**: hi - lo in u S. **Misjudged**: intersection verdicts or within-margin decisions on the wrong side farther than the row's allowance (in u S) from a change of verdict, decided exactly by the oracle. {} cases per query, family and precision; default tolerance ({} u S).\n",
        s.cases,
        Tolerance::DEFAULT.scaled
    );
    let _ = writeln!(a, "## Summary: worst case over all families\n\n| query | variant | prec | max E | median E (worst family) | worst family | max point error | misclassified | interval misses | misjudged | max width | bound E (max / median) | meets |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for &q in Query::ALL {
        for v in Variant::ALL {
            for p in ["f32", "f64"] {
                let rs: Vec<&Row> =
                    acc.iter().filter(|r| r.query == q && r.variant == v && r.precision == p).collect();
                let Some(w) = rs.iter().max_by(|x, y| x.stats.max_excess.total_cmp(&y.stats.max_excess))
                else {
                    continue;
                };
                let sum = |f: fn(&Stats) -> usize| rs.iter().map(|r| f(&r.stats)).sum::<usize>();
                let maxf = |f: fn(&Stats) -> f64| rs.iter().map(|r| f(&r.stats)).fold(0.0, f64::max);
                let all_meet = rs.iter().all(|r| meets(&r.stats, &bound(q, v, p, r.family)));
                let b = bound(q, v, p, w.family);
                let _ = writeln!(
                    a,
                    "| {} | {} | {p} | {} | {} | {} | {} | {} | {} | {} | {} | {} / {} | {} |",
                    q.name(),
                    v.name(),
                    fmt(w.stats.max_excess),
                    fmt(maxf(|s| s.median)),
                    w.family.name(),
                    fmt(maxf(|s| s.max_point_error)),
                    sum(misclassified),
                    sum(|s| s.interval_misses),
                    sum(|s| s.misjudged),
                    fmt(maxf(|s| s.max_width)),
                    fmt(b.max_excess),
                    fmt(b.median),
                    if all_meet { "yes" } else { "**NO**" }
                );
            }
        }
    }
    let mut reasons: Vec<&'static str> = Vec::new();
    for &q in Query::ALL {
        let _ = writeln!(a, "\n## {}\n\n{}\n\n| family | variant | prec | max E | p99 E | median E | max ULP | contact misses | false zeros (beyond 8uS / strict) | non-finite | point error | interval misses | width max / median | misjudged | refined | recertified | compacted | to f64 | uncertified | bound E max / p99 / median / point |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|", q.name(), q.about());
        for f in Family::ALL {
            for r in acc.iter().filter(|r| r.query == q && r.family == f) {
                let st = &r.stats;
                let b = bound(q, r.variant, r.precision, f);
                if !reasons.contains(&b.reason) {
                    reasons.push(b.reason);
                }
                let c = &st.counts;
                let _ = writeln!(
                    a,
                    "| {} | {} | {} | {} | {} | {} | {} | {} | {} / {} | {} | {} | {} | {} / {} | {} | {} | {} | {} | {} | {} | {} / {} / {} / {}{} |",
                    f.name(),
                    r.variant.name(),
                    r.precision,
                    fmt(st.max_excess),
                    fmt(st.p99),
                    fmt(st.median),
                    st.max_ulp.map(fmt).unwrap_or_else(|| "-".into()),
                    st.contact_misses,
                    st.false_zeros,
                    st.strict_false_zeros,
                    st.nonfinite,
                    fmt(st.max_point_error),
                    st.interval_misses,
                    fmt(st.max_width),
                    fmt(st.median_width),
                    st.misjudged,
                    pct(c.refined, c.pairs),
                    pct(c.recertified, c.pairs),
                    pct(c.compacted, c.pairs),
                    pct(c.widened, c.pairs),
                    pct(c.uncertified, c.pairs),
                    fmt(b.max_excess),
                    fmt(b.p99),
                    fmt(b.median),
                    fmt(b.max_point_error),
                    if meets(st, &b) { "" } else { " **EXCEEDED**" }
                );
            }
        }
    }
    a.push_str(&rounded::rounded_md(s.cases, seed));
    let _ = writeln!(a, "\n## Peers against the same oracle\n\nTriangle-triangle distance of the peers, judged on the same cases with the same metrics (distance only: the peers' points are not judged). parry3d / parry3d-f64 `query::distance` on two `Triangle` shapes (GJK), what a Rust user would pick; FCL's `TriangleDistance` (PQP's algorithm, float and double, header-only, built by `scenes/build.rs` with `-O3 -march=native` when `libfcl-dev` and `libeigen3-dev` are installed), what a C++ user would pick. Their distances are squared in the input precision before judging (at most half an ulp more). No bound applies: these are measurements. The last column is tridist's {} on the same cases.\n", best().name());
    for lib in Lib::ALL {
        if !lib.available() {
            let _ = writeln!(a, "- {} not measured: {}\n", lib.name(), lib.missing_reason());
        }
    }
    let _ = writeln!(a, "| peer | family | prec | max E | p99 E | median E | contact misses | false zeros (beyond 8uS / strict) | non-finite | tridist {} max E |\n|---|---|---|---|---|---|---|---|---|---|", best().name());
    for r in &m.peer_acc {
        let st = &r.stats;
        let ours = acc
            .iter()
            .filter(|x| {
                x.query == Query::TriTri
                    && x.variant == best()
                    && x.precision == r.precision
                    && x.family == r.family
            })
            .map(|x| x.stats.max_excess)
            .fold(0.0, f64::max);
        let _ = writeln!(
            a,
            "| {} | {} | {} | {} | {} | {} | {} | {} / {} | {} | {} |",
            r.lib.name(),
            r.family.name(),
            r.precision,
            fmt(st.max_excess),
            fmt(st.p99),
            fmt(st.median),
            st.contact_misses,
            st.false_zeros,
            st.strict_false_zeros,
            st.nonfinite,
            fmt(ours)
        );
    }
    a.push_str(&public_bugs_md());
    let _ = writeln!(a, "\n## The bound table's reasons\n");
    for r in reasons {
        let _ = writeln!(a, "- {r}");
    }
    a
}

/// A section of THROUGHPUT.md that sets another figure of tridist's triangle distance (`alt`:
/// one thread, by workload, variant and precision; named `names.0` in its column and
/// `names.1` in its ratio to FCL) beside the default one, for each shown variant, on the two
/// workloads FCL runs: the default, the other figure, their ratio when `speedup`, and the other
/// figure over FCL's.
fn fcl_section(
    t: &mut String,
    m: &Measured,
    shown: &[&str],
    intro: &str,
    names: (&str, &str),
    alt: &dyn Fn(&str, &str, &str) -> Option<f64>,
    speedup: bool,
) {
    let thr = &m.thr;
    let extra = if speedup { " speed-up |" } else { "" };
    let own: String = shown.iter().map(|v| format!(" tridist {v} | {v} {} |{extra}", names.0)).collect();
    let vs_fcl: String = shown.iter().map(|v| format!(" {v} {} / FCL |", names.1)).collect();
    let per = if speedup { "---|---|---|" } else { "---|---|" };
    let _ = writeln!(
        t,
        "{intro}\n\n| workload | prec |{own} FCL |{vs_fcl}\n|---|---|{}---|{}",
        per.repeat(shown.len()),
        "---|".repeat(shown.len())
    );
    for &(id, title) in m.workloads.iter().filter(|w| w.0 == "random" || w.0 == "arm_nearby") {
        for p in ["f32", "f64"] {
            let fcl = q1(thr, id, Query::TriTri, "fcl", p);
            let both: String = shown
                .iter()
                .map(|v| {
                    let (with, other) = (q1(thr, id, Query::TriTri, v, p), alt(id, v, p));
                    let up = if speedup { format!(" {} |", ratio(other, with)) } else { String::new() };
                    format!(" {} | {} |{up}", mq(with), mq(other))
                })
                .collect();
            let r: String = shown.iter().map(|v| format!(" **{}** |", ratio(alt(id, v, p), fcl))).collect();
            let _ = writeln!(t, "| {title} | {p} |{both} {} |{r}", mq(fcl));
        }
    }
}

fn throughput_md(s: &Settings, seed: u64, m: &Measured) -> String {
    let thr = &m.thr;
    let b = best();
    let bn = b.name();
    let mut t =
        header("Throughput of every kernel variant, and of the peers on the same pairs", &s.command, seed);
    let _ = writeln!(t, "Million queries per second, one thread unless stated, default tolerance, the median of repeated passes over {} pairs per workload (segment-segment: the 9 edge pairs of each triangle pair; point-triangle: the 6 vertex-triangle pairs; within-margin: margin 0.02 on meshes normalised to [-1, 1]^3). Every measurement first checks its results against the scalar AoS variant. Peers run on the same pairs in the same run, after an agreement check. Regenerate with the command above; the criterion benches (`cargo bench -p tridist-benches`) time the same workloads.\n", s.pairs);
    // AVX2+FMA, and the best variant when it is another (AVX-512)
    let shown = shown_variants(bn);
    let own: String = shown.iter().map(|v| format!(" tridist {v} |")).collect();
    let own_fcl: String = shown.iter().map(|v| format!(" {v} / FCL |")).collect();
    let _ = writeln!(t, "## Triangle-triangle distance against the fastest peer\n\n| workload | prec | tridist scalar (AoS) |{own} parry3d | FCL |{own_fcl} {bn} / parry3d | {bn} / scalar |\n|---|---|---|{}---|---|{}---|---|", "---|".repeat(shown.len()), "---|".repeat(shown.len()));
    for &(id, title) in &m.workloads {
        for p in ["f32", "f64"] {
            let ours = q1(thr, id, Query::TriTri, bn, p);
            let parry = q1(thr, id, Query::TriTri, "parry3d", p);
            let fcl = q1(thr, id, Query::TriTri, "fcl", p);
            let each = |f: &dyn Fn(Option<f64>) -> String| -> String {
                shown.iter().map(|v| format!(" {} |", f(q1(thr, id, Query::TriTri, v, p)))).collect()
            };
            let _ = writeln!(
                t,
                "| {title} | {p} | {} |{} {} | {} |{} {} | {} |",
                mq(q1(thr, id, Query::TriTri, "scalar", p)),
                each(&|x| mq(x)),
                mq(parry),
                mq(fcl),
                each(&|x| format!("**{}**", ratio(x, fcl))),
                ratio(ours, parry),
                ratio(ours, q1(thr, id, Query::TriTri, "scalar", p))
            );
        }
    }
    let _ = writeln!(t, "\nFCL is double-precision PQP `TriangleDistance` (FCL 0.7, `-O3 -march=native`); its float column is the same template instantiated for float. Agreement of each peer with tridist on these pairs (largest |d - d'| / S over the pairs, pairs beyond 1e-3 S):\n");
    for a in &m.agree {
        let c = match &a.check {
            Ok((w, n)) => format!("{w:.1e}, {n} beyond"),
            Err(e) => format!("{e} (beyond 1e-3 S; timed all the same)"),
        };
        let _ = writeln!(t, "- {} {} {}: {c}", a.workload, a.lib.name(), a.precision);
    }
    for lib in Lib::ALL.iter().filter(|l| !l.available()) {
        let _ = writeln!(t, "- {} not measured: {}", lib.name(), lib.missing_reason());
    }
    fcl_section(
        &mut t,
        m,
        &shown,
        "\n## With closest points: like for like with FCL\n\nFCL's `TriangleDistance` always computes the closest points. The table above times tridist writing squared distances alone, the cheapest output (what a caller that asks only for distances gets). Here tridist also writes the closest points (`Outputs::closest_points`), the output FCL's figure includes; the squared distances of that pass are first checked, bit for bit, against the pass without points. Million pairs per second, one thread.",
        ("with points", "with points"),
        &|id, v, p| q1_points(thr, id, v, p),
        false,
    );
    fcl_section(
        &mut t,
        m,
        &shown,
        "\n## Without the quick stage: arbitrary pairs\n\nTriangle distance starts with a quick stage (one edge pair per triangle pair) that answers nearly every pair of nearby mesh triangles; the pairs it leaves open are gathered for the full fast stage (fifteen candidates and contact) and pay for both. `Engine::quick_stage(false)` sends every pair straight to the full fast stage, for batches of arbitrary pairs (\"refined\" in the table below is the share the quick stage leaves open). Both settings meet the same bounds (the differential suite runs both). Squared distances alone, million pairs per second, one thread; the speed-up is without over with.",
        ("without the quick stage", "without"),
        &|id, v, p| q1_full(thr, id, v, p),
        true,
    );
    let _ = writeln!(t, "\n## Where the pairs go ({bn}, default tolerance)\n\nThe certified pipeline: a fast stage answers every pair with an interval (for triangle-triangle distance a quick stage on one edge pair per triangle pair, then, for the pairs it leaves open, gathered into full vectors, the full fast stage on all fifteen candidates: refined); pairs whose interval is wider than the tolerance are re-certified with the tight certificate, then recomputed by the accurate stage in compacted full vectors, then (f32) in f64 from the exactly widened input. Intersection and within-margin first run a cheap test and hand the undecided pairs on (delegated). Percent of the pairs of one pass.\n\n| workload | query | prec | pairs | prefiltered | delegated | refined | recertified | compacted | to f64 | exact | uncertified |\n|---|---|---|---|---|---|---|---|---|---|---|---|");
    for &(id, title) in &m.workloads {
        for r in thr.iter().filter(|r| {
            r.workload == id
                && r.implementation == bn
                && r.threads == 1
                && r.tolerance == "default"
                && r.plain()
        }) {
            let c = &r.counts;
            let _ = writeln!(
                t,
                "| {title} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                r.query,
                r.precision,
                c.pairs,
                pct(c.prefiltered, c.pairs),
                pct(c.delegated, c.pairs),
                pct(c.refined, c.pairs),
                pct(c.recertified, c.pairs),
                pct(c.compacted, c.pairs),
                pct(c.widened, c.pairs),
                pct(c.exact, c.pairs),
                pct(c.uncertified, c.pairs)
            );
        }
    }
    let _ = writeln!(t, "\n## The tolerance knob (triangle-triangle, {bn})\n\n`Engine::tolerance`: a pair is done when its certified interval is at most the tolerance wide (`exact`: only exact intervals; `scaled:K`: K u S; `default`: {} u S; `abs:X`: X in the input's units). Tighter tolerances send more pairs down the slower stages; the accuracy report gives the widths actually reached. `correctly-rounded` (`Tolerance::CORRECTLY_ROUNDED`): every squared distance is the exact one rounded to nearest, decided from the f64 answer's interval (to f64: every f32 pair is answered in f64) or by the exact oracle; *undecided* pairs are those neither could decide in this build (the reports' build has no `exact` feature, so for f64 input nearly every pair: that row's rate is not a correctly rounded rate).\n\n| workload | prec | tolerance | Mq/s | refined | recertified | compacted | to f64 | exact | uncertified | undecided |\n|---|---|---|---|---|---|---|---|---|---|---|", Tolerance::DEFAULT.scaled);
    for &(id, title) in &m.workloads {
        for p in ["f32", "f64"] {
            for (name, _) in TOLERANCES {
                let Some(r) = thr.iter().find(|r| {
                    r.workload == id
                        && r.query == "tri_tri"
                        && r.implementation == bn
                        && r.precision == p
                        && r.threads == 1
                        && r.tolerance == name
                        && r.plain()
                }) else {
                    continue;
                };
                let c = &r.counts;
                let _ = writeln!(
                    t,
                    "| {title} | {p} | {name} | {:.2} | {} | {} | {} | {} | {} | {} | {} |",
                    r.qps / 1e6,
                    pct(c.refined, c.pairs),
                    pct(c.recertified, c.pairs),
                    pct(c.compacted, c.pairs),
                    pct(c.widened, c.pairs),
                    pct(c.exact, c.pairs),
                    pct(c.uncertified, c.pairs),
                    pct(c.undecided, c.pairs)
                );
            }
        }
    }
    let _ = writeln!(t, "\n## Threads (triangle-triangle, {bn})\n\n`Engine::threads(n)`: the calling thread and a persistent pool of n - 1 helpers, batches of at least {} pairs split into pieces of at least {} pairs, the calling thread taking them from the front and the helpers from the back, the caller waiting awake (up to {} µs) for the helpers' last pieces. Measured alternately on the same batch (three rounds, medians): one thread, two threads, and, as the machine's ceiling at that moment, two independent one-thread workers each answering the whole batch (their combined rate over one thread's). Batches: the workload's pairs, and the same pairs repeated to {LARGE_BATCH}.\n\n| workload | prec | pairs | 1 thread Mq/s | 2 threads Mq/s | speed-up | 2 independent workers |\n|---|---|---|---|---|---|---|", tridist::Engine::MIN_PARALLEL, tridist::Engine::PIECE, tridist::Engine::WAIT_AWAKE.as_micros());
    for &(id, title) in &m.workloads {
        for r in m.threads.iter().filter(|r| r.workload == id) {
            let _ = writeln!(
                t,
                "| {title} | {} | {} | {} | {} | {} | {} |",
                r.precision,
                r.pairs,
                mq(Some(r.one)),
                mq(Some(r.two)),
                ratio(Some(r.two), Some(r.one)),
                ratio(Some(r.apart), Some(r.one))
            );
        }
    }
    for &(id, title) in &m.workloads {
        let names: String = Variant::ALL[1..].iter().map(|v| format!(" {} |", v.name())).collect();
        let rule = "---|".repeat(Variant::ALL.len());
        let _ = writeln!(t, "\n## {title}\n\n| query | prec | scalar (AoS) |{names}\n|---|---|{rule}");
        for q in queries_of(id) {
            for p in ["f32", "f64"] {
                let cells: Vec<String> =
                    Variant::ALL.iter().map(|v| mq(q1(thr, id, q, v.name(), p))).collect();
                let _ = writeln!(t, "| {} | {p} | {} |", q.name(), cells.join(" | "));
            }
        }
    }
    let rw = "random";
    let _ = writeln!(
        t,
        "\n## Ratios (random unit cube, tri-tri unless named)\n\n| comparison | f32 | f64 |\n|---|---|---|"
    );
    let comps: [(&str, &str, &str); 7] = [
        ("AVX2+FMA vs scalar AoS", "avx2fma", "scalar"),
        ("AVX2+FMA vs SSE4.1", "avx2fma", "sse41"),
        ("AVX (no FMA) vs SSE4.1", "avx", "sse41"),
        ("AVX2+FMA vs AVX (FMA effect)", "avx2fma", "avx"),
        ("scalar SoA vs scalar AoS (layout)", "soa", "scalar"),
        ("AVX-512 vs AVX2+FMA (16/8 lanes against 8/4)", "avx512", "avx2fma"),
        ("AVX-512VL vs AVX2+FMA (32 registers against 16)", "avx512vl", "avx2fma"),
    ];
    for (label, x, y) in comps {
        let r = |p| ratio(q1(thr, rw, Query::TriTri, x, p), q1(thr, rw, Query::TriTri, y, p));
        let _ = writeln!(t, "| {label} | {} | {} |", r("f32"), r("f64"));
    }
    let r = |p| ratio(q1(thr, rw, Query::TriTri, bn, p), q1(thr, rw, Query::TriTriBrute, bn, p));
    let _ = writeln!(t, "| PQP vs brute force ({bn}) | {} | {} |", r("f32"), r("f64"));
    let wf = "arm_arm_random";
    let r = |p| ratio(q1(thr, wf, Query::Within, bn, p), q1(thr, wf, Query::TriTri, bn, p));
    let _ = writeln!(
        t,
        "| within-margin 0.02 vs full query, mostly far pairs (Armadillo random, {bn}) | {} | {} |",
        r("f32"),
        r("f64")
    );
    let _ = writeln!(
        t,
        "| f32 vs f64 ({bn}) | {} | |",
        ratio(q1(thr, rw, Query::TriTri, bn, "f32"), q1(thr, rw, Query::TriTri, bn, "f64"))
    );
    if !m.failed.is_empty() {
        let _ = writeln!(t, "\n## Result checks that failed\n");
        for f in &m.failed {
            let _ = writeln!(t, "- {f}");
        }
    }
    let _ = writeln!(t, "\nMachine-readable: [throughput.csv](throughput.csv) (every row above, read by `tridist advise`; columns: {}; `outputs` is `answer` for squared distances or verdicts alone, `points` when closest points were written too, as FCL always does). The Stanford Armadillo is courtesy of the Stanford Computer Graphics Laboratory.", table::HEADER.join(", "));
    t
}

/// Every variant and peer: throughput on random pairs against worst-family and median E.
fn tradeoff_plot(m: &Measured) -> Plot {
    let mut series = Vec::new();
    let mut add = |label: String, colour: usize, mark: Mark, x: Option<f64>, max: f64, med: f64| {
        let Some(x) = x else { return };
        let x = x / 1e6;
        // An infinite E (a non-finite answer for finite input) is drawn at the cap, and says so
        // in the legend, rather than dropped from the picture.
        const CAP: f64 = 1e18;
        let label = if max.is_finite() { label } else { format!("{label} (max E = inf, drawn at 1e18)") };
        let (max, med) = (max.clamp(1e-3, CAP), med.clamp(1e-3, CAP));
        series.push(Series { label, points: vec![(x, max)], mark, colour, whiskers: vec![(x, med, max)] });
    };
    let worst = |rows: Vec<&Stats>| -> (f64, f64) {
        (
            rows.iter().map(|s| s.max_excess).fold(0.0, f64::max),
            rows.iter().map(|s| s.median).fold(0.0, f64::max),
        )
    };
    for (i, v) in Variant::ALL.into_iter().enumerate() {
        for (p, mark) in [("f32", Mark::Triangle), ("f64", Mark::Circle)] {
            let (mx, md) = worst(
                m.acc
                    .iter()
                    .filter(|r| r.query == Query::TriTri && r.variant == v && r.precision == p)
                    .map(|r| &r.stats)
                    .collect(),
            );
            add(
                format!("tridist {} {p}", v.name()),
                i,
                mark,
                q1(&m.thr, "random", Query::TriTri, v.name(), p),
                mx,
                md,
            );
        }
    }
    for (i, lib) in Lib::ALL.into_iter().enumerate() {
        for (p, mark) in [("f32", Mark::Cross), ("f64", Mark::Ring)] {
            let (mx, md) = worst(
                m.peer_acc.iter().filter(|r| r.lib == lib && r.precision == p).map(|r| &r.stats).collect(),
            );
            add(
                format!("{} {p}", lib.name()),
                6 + i,
                mark,
                q1(&m.thr, "random", Query::TriTri, lib.name(), p),
                mx,
                md,
            );
        }
    }
    Plot {
        title: "Triangle-triangle distance: throughput vs error".into(),
        xlabel: "million queries/s (random unit-cube pairs, 1 thread)".into(),
        ylabel: "excess E: marker = worst family, whisker down to the worst median".into(),
        series,
        hline: Some((bound_target(), "target E = 8".into())),
    }
}

fn penalty_plot(p32: &[PenaltyRow], p64: &[PenaltyRow]) -> Plot {
    let mut series = Vec::new();
    for (i, (p, rows)) in [("f32", p32), ("f64", p64)].into_iter().enumerate() {
        series.push(Series::line(
            format!("median E {p}"),
            2 * i,
            rows.iter().map(|r| (r.max_iter as f64, r.median.max(1e-3))).collect(),
        ));
        series.push(Series::line(
            format!("p99 E {p}"),
            2 * i + 1,
            rows.iter().map(|r| (r.max_iter as f64, r.p99.max(1e-3))).collect(),
        ));
    }
    Plot {
        title: "Penalty method: error vs iterations (random unit-cube pairs)".into(),
        xlabel: "Newton iterations (max_iter, tol = 0)".into(),
        ylabel: "excess E".into(),
        series,
        hline: Some((bound_target(), "target E = 8".into())),
    }
}

fn tradeoff_md(s: &Settings, seed: u64, m: &Measured, p32: &[PenaltyRow], p64: &[PenaltyRow]) -> String {
    let mut tr = header("Speed for accuracy: what each variant costs and what it buys", &s.command, seed);
    let _ = writeln!(tr, "Each marker is one implementation and precision of triangle-triangle distance: its throughput on random unit-cube pairs (one thread) against its worst excess E over every input family; the whisker reaches down to its worst per-family median. tridist variants and the peers (parry3d, FCL) are judged by the same oracle on the same cases. Lower right is better; under the dashed line meets the E <= 8 target on every family. E below 1e-3 is drawn at 1e-3.\n\n![throughput vs error](tradeoff.svg)\n");
    let _ = writeln!(tr, "## Per family (max excess E, triangle-triangle)\n\n| implementation | prec | Mq/s | {} |\n|---|---|---|{}", Family::ALL.iter().map(|f| f.name()).collect::<Vec<_>>().join(" | "), "---|".repeat(Family::ALL.len()));
    for v in Variant::ALL {
        for p in ["f32", "f64"] {
            let cells: Vec<String> = Family::ALL
                .iter()
                .map(|&f| {
                    m.acc
                        .iter()
                        .find(|r| {
                            r.query == Query::TriTri && r.variant == v && r.precision == p && r.family == f
                        })
                        .map(|r| fmt(r.stats.max_excess))
                        .unwrap_or_else(|| "-".into())
                })
                .collect();
            let _ = writeln!(
                tr,
                "| tridist {} | {p} | {} | {} |",
                v.name(),
                mq(q1(&m.thr, "random", Query::TriTri, v.name(), p)),
                cells.join(" | ")
            );
        }
    }
    for lib in Lib::ALL.into_iter().filter(|l| l.available()) {
        for p in ["f32", "f64"] {
            let cells: Vec<String> = Family::ALL
                .iter()
                .map(|&f| {
                    m.peer_acc
                        .iter()
                        .find(|r| r.lib == lib && r.precision == p && r.family == f)
                        .map(|r| fmt(r.stats.max_excess))
                        .unwrap_or_else(|| "-".into())
                })
                .collect();
            let _ = writeln!(
                tr,
                "| {} | {p} | {} | {} |",
                lib.name(),
                mq(q1(&m.thr, "random", Query::TriTri, lib.name(), p)),
                cells.join(" | ")
            );
        }
    }
    let _ = writeln!(tr, "\n## Stability at the extremes\n\nEvery query scales its input by a power of two before computing, so the error relative to the magnitude stays flat from tiny to huge coordinates and far from the origin. Decades whose worst excess is below 1e-3 are drawn at 1e-3.\n\n![error vs magnitude](magnitude.svg)\n\n![error vs offset](offset.svg)\n\n## Penalty method: iterations against error and time\n");
    let _ = writeln!(tr, "Krestenitis & Koziara's penalty method on random unit-cube pairs ({} cases), {} variant, default rho and regularisation, tolerance 0 so that every pair runs exactly `max_iter` steps. E is the excess error of the returned (feasible) points; time per query from one timed pass.\n\n![penalty iterations](penalty.svg)\n\n| precision | max_iter | median E | p99 E | max E | Mq/s |\n|---|---|---|---|---|---|", s.cases * 2, best().name());
    for (p, rows) in [("f32", p32), ("f64", p64)] {
        for r in rows {
            let _ = writeln!(
                tr,
                "| {p} | {} | {} | {} | {} | {:.2} |",
                r.max_iter,
                fmt(r.median),
                fmt(r.p99),
                fmt(r.max),
                r.qps / 1e6
            );
        }
    }
    tr
}

/// The public-bug set (scenes/tests/regressions/public_bugs.txt) judged like the families: the
/// worst excess E of tridist over every variant on the labelled query, and the peers' triangle
/// distance on the same line (points and segments are degenerate triangles there, so the
/// triangle-triangle distance is the labelled query's).
fn public_bugs_md() -> String {
    let mut a = String::from("\n## Public-bug set\n\nCases reconstructed from public issue trackers of distance and collision libraries ([scenes/tests/regressions/public_bugs.txt](../scenes/tests/regressions/public_bugs.txt), each line names the project and issue), read in both precisions and judged with the same metrics. tridist: the worst E over every variant on the labelled query (`!` marks a misclassification: contact miss, false zero beyond 8 u S or non-finite). Peers: their triangle-triangle distance on the same pair.\n\n| case | query | prec | exact d | tridist worst E | parry3d E | fcl E |\n|---|---|---|---|---|---|---|\n");
    public_bug_rows::<f32>(&mut a);
    public_bug_rows::<f64>(&mut a);
    a
}

fn public_bug_rows<T: Peer>(a: &mut String) {
    let bad = |st: &Stats| st.contact_misses + st.false_zeros + st.nonfinite + st.misjudged > 0;
    let mark = |max: f64, bad: bool| format!("{}{}", fmt(max), if bad { " !" } else { "" });
    for line in
        tridist_scenes::PUBLIC_BUGS.lines().map(str::trim).filter(|l| !l.is_empty() && !l.starts_with('#'))
    {
        let Ok((case, _)) = tridist_scenes::eval::parse_case_line_exact::<T>(line) else { continue };
        let Some(q) = case.label.split('/').next().and_then(Query::parse) else { continue };
        let cases = vec![case];
        let tr = truth(q, &cases);
        // Over our variants: the largest excess, and whether any variant misclassified (not
        // necessarily the one with the largest excess).
        let mut ours: Option<(f64, bool)> = None;
        for v in Variant::ALL {
            let Ok(out) = tridist_scenes::eval::run(q, v, &cases, None) else { continue };
            let st = summarise(q, &cases, &tr, &out, bound(q, v, T::NAME, Family::Degenerate).allow, None).0;
            let (m, b) = ours.unwrap_or((0.0, false));
            ours = Some((m.max(st.max_excess), b || bad(&st)));
        }
        let peer = |lib: Lib| {
            if lib.available() {
                let st = peer::judge_cases(lib, &cases);
                mark(st.max_excess, bad(&st))
            } else {
                "-".into()
            }
        };
        let _ = writeln!(
            a,
            "| {} | {} | {} | {:.6e} | {} | {} | {} |",
            cases[0].label.split_once('/').map_or("", |x| x.1),
            q.name(),
            T::NAME,
            tr[0].d2.to_f64().sqrt(),
            ours.map_or("-".into(), |(m, b)| mark(m, b)),
            peer(Lib::Parry),
            peer(Lib::Fcl)
        );
    }
}
