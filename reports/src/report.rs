//! `tridist report`: the accuracy sweep, the throughput measurement and the trade-off plots,
//! written to `reports/` and summarised in the README between the results markers.

use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::Path;
use std::time::Duration;

use tridist::Real;
use tridist_scenes::bounds::bound;
use tridist_scenes::eval::{run, summarise, sweep_family, truth, Query, Row, Stats, Variant};
use tridist_scenes::mesh;
use tridist_scenes::peer::{self, Peer};
use tridist_scenes::protocol::{self, Grouping};
use tridist_scenes::{families, Family};

use crate::common::{fmt, header, Progress};
use crate::svg::{Plot, Series};
use tridist_scenes::workload::{measure, TQuery, Workload};

type Pairs = Vec<(tridist::Triangle<f64>, tridist::Triangle<f64>)>;

/// Report settings.
pub struct Settings {
    /// Cases per (query, family, precision).
    pub cases: usize,
    /// Pairs per throughput workload.
    pub pairs: usize,
    /// Time budget per throughput measurement.
    pub budget: Duration,
    /// The command line to print in headers.
    pub command: String,
    /// Where to write.
    pub out_dir: std::path::PathBuf,
    /// README to update (between the results markers), if any.
    pub readme: Option<std::path::PathBuf>,
}

/// One throughput figure.
#[derive(Clone, Debug)]
pub struct TRow {
    /// Workload name.
    pub workload: String,
    /// Query.
    pub query: TQuery,
    /// Variant.
    pub variant: Variant,
    /// Precision.
    pub precision: &'static str,
    /// Queries per second (or an error).
    pub qps: Result<f64, String>,
}

fn accuracy(s: &Settings, prog: &mut Progress) -> Vec<Row> {
    let seed = tridist_scenes::seed();
    let mut rows = Vec::new();
    for q in Query::ALL {
        for f in Family::ALL {
            rows.extend(sweep_family::<f32>(q, f, seed, s.cases, |_, _| {}));
            rows.extend(sweep_family::<f64>(q, f, seed, s.cases, |_, _| {}));
            prog.step(&format!("accuracy {} {}", q.name(), f.name()));
        }
    }
    rows
}

fn workloads(s: &Settings) -> Result<Vec<(String, Pairs)>, String> {
    let load = |n: &str| mesh::carried(n).map_err(|e| e.to_string());
    let arm = load("armadillo.off")?;
    let fan = load("fandisk_large.off")?;
    let seed = tridist_scenes::seed();
    let mut w = Vec::new();
    let rnd: Vec<_> =
        families::generate::<f64>(Family::Random, seed, s.pairs).into_iter().map(|c| (c.a, c.b)).collect();
    w.push(("random unit cube".to_string(), rnd));
    for (name, a, b) in [
        ("Fandisk vs Fandisk", &fan, &fan),
        ("Fandisk vs Armadillo", &fan, &arm),
        ("Armadillo vs Armadillo", &arm, &arm),
    ] {
        for g in [Grouping::Neighbouring, Grouping::Random] {
            w.push((format!("{name}, {} triangles", g.name()), protocol::pairs(a, b, g, s.pairs, seed)));
        }
    }
    Ok(w)
}

fn throughput(s: &Settings, prog: &mut Progress) -> Result<Vec<TRow>, String> {
    let mut out = Vec::new();
    for (name, pairs) in workloads(s)? {
        let queries: &[TQuery] = if name == "random unit cube" {
            &TQuery::ALL
        } else {
            &[TQuery::TriPoint, TQuery::SegSeg, TQuery::TriTri, TQuery::Within]
        };
        let w32 = Workload::<f32>::new(&pairs, 0.02);
        let w64 = Workload::<f64>::new(&pairs, 0.02);
        for &q in queries {
            for v in Variant::ALL {
                if let Some(r) = measure(&w32, q, v, s.budget) {
                    out.push(TRow { workload: name.clone(), query: q, variant: v, precision: "f32", qps: r });
                }
                if let Some(r) = measure(&w64, q, v, s.budget) {
                    out.push(TRow { workload: name.clone(), query: q, variant: v, precision: "f64", qps: r });
                }
            }
            prog.step(&format!("throughput {} {}", q.name(), name));
        }
    }
    Ok(out)
}

/// The peer (parry3d / parry3d-f64 triangle distance) on one workload and precision.
#[derive(Clone, Debug)]
pub struct PeerRow {
    /// Workload name.
    pub workload: String,
    /// Precision.
    pub precision: &'static str,
    /// Queries per second, the largest `|d - d'| / S` against tridist and the pairs beyond
    /// `1e-3` (or why the agreement check failed).
    pub measured: Result<(f64, f64, usize), String>,
}

fn peer_one<T: Peer>(pairs: &Pairs, budget: Duration) -> Result<(f64, f64, usize), String> {
    let w = Workload::<T>::new(pairs, 0.02);
    let (a, b) = w.triangles();
    let (worst, beyond) = peer::agreement(a, b)?;
    let secs = peer::time_pass(&peer::Shapes::new(a, b), budget);
    Ok((a.len() as f64 / secs, worst, beyond))
}

fn peer_throughput(s: &Settings, prog: &mut Progress) -> Result<Vec<PeerRow>, String> {
    let mut out = Vec::new();
    for (name, pairs) in workloads(s)? {
        out.push(PeerRow {
            workload: name.clone(),
            precision: "f32",
            measured: peer_one::<f32>(&pairs, s.budget),
        });
        out.push(PeerRow {
            workload: name.clone(),
            precision: "f64",
            measured: peer_one::<f64>(&pairs, s.budget),
        });
        prog.step(&format!("throughput parry3d {name}"));
    }
    Ok(out)
}

fn peer_accuracy(s: &Settings, prog: &mut Progress) -> Vec<(Family, &'static str, Stats)> {
    let seed = tridist_scenes::seed();
    let mut out = Vec::new();
    for f in Family::ALL {
        out.push((f, "f32", peer::judge::<f32>(f, seed, s.cases)));
        out.push((f, "f64", peer::judge::<f64>(f, seed, s.cases)));
        prog.step(&format!("accuracy parry3d {}", f.name()));
    }
    out
}

/// The peer's measured queries per second on a workload and precision.
fn peer_qps(t: &[PeerRow], workload: &str, p: &str) -> Option<f64> {
    t.iter()
        .find(|r| r.workload == workload && r.precision == p)
        .and_then(|r| r.measured.as_ref().ok())
        .map(|m| m.0)
}

fn qps(t: &[TRow], workload: &str, q: TQuery, v: Variant, p: &str) -> Option<f64> {
    t.iter()
        .find(|r| r.workload == workload && r.query == q && r.variant == v && r.precision == p)
        .and_then(|r| r.qps.clone().ok())
}

fn best_simd() -> Variant {
    Variant::from_isa(tridist::Isa::best())
}

/// Per-case excess E and magnitude for the stability plots.
fn per_case<T: Real>(q: Query, family: Family, v: Variant, n: usize) -> Vec<(f64, f64)> {
    let cases = families::generate::<T>(family, tridist_scenes::seed() ^ 0xface, n);
    let tr = truth(q, &cases);
    let Ok(out) = run(q, v, &cases) else { return Vec::new() };
    let (_, js) = summarise(q, &cases, &tr, &out);
    js.iter().zip(&tr).map(|(j, t)| (t.s, j.excess)).collect()
}

/// Max over decade bins of x.
fn binned(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut m: BTreeMap<i64, f64> = BTreeMap::new();
    for &(x, y) in points {
        if x > 0.0 && y.is_finite() {
            let k = x.log10().floor() as i64;
            let e = m.entry(k).or_insert(0.0);
            *e = e.max(y);
        }
    }
    m.into_iter().map(|(k, y)| (10f64.powi(k as i32) * 3.16, y.max(1e-3))).collect()
}

/// (max_iter, median E, p99 E, max E, queries/s) of the penalty method with tolerance 0.
fn penalty_sweep<T: Real>(v: Variant, n: usize) -> Vec<(u32, f64, f64, f64, f64)> {
    let cases = families::generate::<T>(Family::Random, tridist_scenes::seed(), n);
    let tr = truth(Query::Penalty, &cases);
    let mut out = Vec::new();
    for it in [1u32, 2, 3, 4, 6, 8, 16, 32] {
        let opts = tridist::PenaltyOptions {
            tol: T::ZERO + T::MIN_POSITIVE,
            max_iter: it,
            ..tridist::PenaltyOptions::default()
        };
        let mut o = tridist_scenes::eval::Output::default();
        let t0 = std::time::Instant::now();
        if tridist_scenes::eval::run_penalty(v, &cases, &opts, &mut o).is_err() {
            continue;
        }
        let secs = t0.elapsed().as_secs_f64().max(1e-9);
        let (st, _) = summarise(Query::Penalty, &cases, &tr, &o);
        out.push((it, st.median, st.p99, st.max_excess, n as f64 / secs));
    }
    out
}

/// The binned per-case error of triangle-triangle on `family` for one variant, f32 and f64.
fn stability(family: Family, v: Variant, n: usize) -> [Series; 2] {
    [
        Series::line(format!("{} f32", v.name()), binned(&per_case::<f32>(Query::TriTri, family, v, n))),
        Series::line(format!("{} f64", v.name()), binned(&per_case::<f64>(Query::TriTri, family, v, n))),
    ]
}

fn write_file(dir: &Path, name: &str, text: &str) -> Result<(), String> {
    std::fs::write(dir.join(name), text).map_err(|e| format!("{}: {e}", dir.join(name).display()))
}

/// Runs the whole report.
pub fn run_report(s: &Settings) -> Result<(), String> {
    std::fs::create_dir_all(&s.out_dir).map_err(|e| format!("{}: {e}", s.out_dir.display()))?;
    let seed = tridist_scenes::seed();
    let mut prog = Progress::new((Query::ALL.len() + 1) * Family::ALL.len() + 7 + 6 * 4 + 7 + 4 + 2);
    let acc = accuracy(s, &mut prog);
    let peer_acc = peer_accuracy(s, &mut prog);
    let thr = throughput(s, &mut prog)?;
    let peer_thr = peer_throughput(s, &mut prog)?;
    // stability curves
    let simd = best_simd();
    let mut mag = Vec::new();
    let mut off = Vec::new();
    for v in [Variant::Scalar, simd] {
        mag.extend(stability(Family::Scale, v, s.cases * 2));
        prog.step("stability: magnitude");
        off.extend(stability(Family::Far, v, s.cases * 2));
        prog.step("stability: offset");
    }

    // ---------- ACCURACY.md ----------
    let mut a = header("Accuracy of every kernel variant against the exact oracle", &s.command, seed);
    let _ = writeln!(
        a,
        "Metrics as defined in [docs/ACCURACY.md](../docs/ACCURACY.md): **E** = |sqrt(D^) - d*| / (u S), reported as the *excess* over the correctly rounded exact answer; ULP error of the squared distance where D* >= (2^10 u S)^2; contact misses (D* = 0 reported above 8 u S); false zeros beyond 8 u S (and, strictly, any positive D* reported as 0); non-finite outputs for finite input; closest-point error (offset of a returned point from its primitive, or |p - q| against d*, scaled like E). {} cases per query, family and precision.\n",
        s.cases
    );
    let _ = writeln!(a, "## Summary: worst case over all families\n\n| query | variant | precision | max E | worst family | max point error | misclassified | bound E |\n|---|---|---|---|---|---|---|---|");
    for q in Query::ALL {
        for v in Variant::ALL {
            for p in ["f32", "f64"] {
                let rs: Vec<&Row> =
                    acc.iter().filter(|r| r.query == q && r.variant == v && r.precision == p).collect();
                let Some(w) = rs.iter().max_by(|x, y| x.stats.max_excess.total_cmp(&y.stats.max_excess))
                else {
                    continue;
                };
                let pe = rs.iter().map(|r| r.stats.max_point_error).fold(0.0, f64::max);
                let mis: usize =
                    rs.iter().map(|r| r.stats.contact_misses + r.stats.false_zeros + r.stats.nonfinite).sum();
                let b = bound(q, v, p, w.family);
                let _ = writeln!(
                    a,
                    "| {} | {} | {p} | {} | {} | {} | {mis} | {} |",
                    q.name(),
                    v.name(),
                    fmt(w.stats.max_excess),
                    w.family.name(),
                    fmt(pe),
                    fmt(b.max_excess)
                );
            }
        }
    }
    let mut reasons: Vec<&'static str> = Vec::new();
    for q in Query::ALL {
        let _ = writeln!(a, "\n## {}\n\n| family | variant | prec | max E | p99 E | median E | max ULP | contact misses | false zeros (beyond 8uS / strict) | non-finite | point error | bound E / point |\n|---|---|---|---|---|---|---|---|---|---|---|---|", q.name());
        for f in Family::ALL {
            for r in acc.iter().filter(|r| r.query == q && r.family == f) {
                let st = &r.stats;
                let b = bound(q, r.variant, r.precision, f);
                if !reasons.contains(&b.reason) {
                    reasons.push(b.reason);
                }
                let within = st.max_excess <= b.max_excess
                    && st.max_point_error <= b.max_point_error
                    && st.contact_misses + st.false_zeros + st.nonfinite <= b.max_misclassified;
                let _ = writeln!(
                    a,
                    "| {} | {} | {} | {} | {} | {} | {} | {} | {} / {} | {} | {} | {} / {}{} |",
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
                    fmt(b.max_excess),
                    fmt(b.max_point_error),
                    if within { "" } else { " **EXCEEDED**" }
                );
            }
        }
    }
    let _ = writeln!(a, "\n## Peer: parry3d / parry3d-f64 against the same oracle\n\nparry's `query::distance` on two `Triangle` shapes (GJK), what a Rust user would pick today, judged on the same cases with the same metrics (distance only: it returns no points; its distance is squared in the input precision before judging, which adds at most half an ulp). The last column is tridist's {} PQP kernel on the same cases. No bound applies: these are measurements. Where parry reports 0 for pairs that are apart (false zeros, mostly on the scale family), its stopping tolerances are absolute and do not follow the input's magnitude.\n\n| family | prec | max E | p99 E | median E | contact misses | false zeros (beyond 8uS / strict) | non-finite | tridist {} max E |\n|---|---|---|---|---|---|---|---|---|", best_simd().name(), best_simd().name());
    for (f, p, st) in &peer_acc {
        let ours = acc
            .iter()
            .filter(|r| {
                r.query == Query::TriTri && r.variant == best_simd() && r.precision == *p && r.family == *f
            })
            .map(|r| r.stats.max_excess)
            .fold(0.0, f64::max);
        let _ = writeln!(
            a,
            "| {} | {p} | {} | {} | {} | {} | {} / {} | {} | {} |",
            f.name(),
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
    let _ = writeln!(a, "\n## The bound table's reasons\n");
    for r in reasons {
        let _ = writeln!(a, "- {r}");
    }
    write_file(&s.out_dir, "ACCURACY.md", &a)?;

    // ---------- THROUGHPUT.md + CSV ----------
    let mut t = header("Throughput of every kernel variant", &s.command, seed);
    let _ = writeln!(t, "Millions of queries per second, one thread, {} pairs per workload (segment pairs: 9 per triangle pair, point-triangle: 6), median of repeated passes after a warm-up. Every figure was checked against the scalar AoS results first. Layouts as in Shellshear & Ytterlid: **SIMD** = the best available vector variant over SoA columns ({}), **SIMD layout** = scalar over SoA columns, **non-SIMD layout** = scalar over plain triangle arrays. fandisk (a CAD part) stands in for the paper's proprietary cembox.\n", s.pairs, best_simd().name());
    let mut csv = String::from("workload,query,variant,precision,queries_per_second\n");
    for r in &thr {
        if let Ok(v) = r.qps {
            let _ = writeln!(
                csv,
                "{},{},{},{},{v:.1}",
                r.workload,
                r.query.name(),
                r.variant.name(),
                r.precision
            );
        }
    }
    let mq = |x: Option<f64>| x.map(|v| format!("{:.2}", v / 1e6)).unwrap_or_else(|| "-".into());
    for p in ["f32", "f64"] {
        let _ = writeln!(t, "## Paper protocol ({p})\n");
        for (wl, _) in workloads(s)?.iter().skip(1) {
            let _ = writeln!(
                t,
                "### {wl}\n\n| layout | tri-point | seg-seg | tri-tri | within 0.02 |\n|---|---|---|---|---|"
            );
            for (label, v) in
                [("SIMD", best_simd()), ("SIMD layout", Variant::Soa), ("non-SIMD layout", Variant::Scalar)]
            {
                let _ = writeln!(
                    t,
                    "| {label} | {} | {} | {} | {} |",
                    mq(qps(&thr, wl, TQuery::TriPoint, v, p)),
                    mq(qps(&thr, wl, TQuery::SegSeg, v, p)),
                    mq(qps(&thr, wl, TQuery::TriTri, v, p)),
                    mq(qps(&thr, wl, TQuery::Within, v, p))
                );
            }
            let _ = writeln!(t);
        }
    }
    let rw = "random unit cube";
    let _ = writeln!(t, "## Every query, variant and precision on random unit-cube pairs\n\n| query | precision | scalar (AoS) | soa | sse41 | avx | avx2fma |\n|---|---|---|---|---|---|---|");
    for q in TQuery::ALL {
        for p in ["f32", "f64"] {
            let cells: Vec<String> = Variant::ALL.iter().map(|&v| mq(qps(&thr, rw, q, v, p))).collect();
            let _ = writeln!(t, "| {} | {p} | {} |", q.name(), cells.join(" | "));
        }
    }
    let ratio = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(x), Some(y)) if y > 0.0 => format!("{:.2}x", x / y),
        _ => "-".into(),
    };
    let _ = writeln!(
        t,
        "\n## Ratios (random unit cube, tri-tri unless named)\n\n| comparison | f32 | f64 |\n|---|---|---|"
    );
    let comps: [(&str, TQuery, Variant, Variant); 6] = [
        ("AVX2+FMA vs scalar AoS", TQuery::TriTri, Variant::Avx2Fma, Variant::Scalar),
        ("AVX2+FMA vs SSE4.1", TQuery::TriTri, Variant::Avx2Fma, Variant::Sse41),
        ("AVX (no FMA) vs SSE4.1", TQuery::TriTri, Variant::Avx, Variant::Sse41),
        ("AVX2+FMA vs AVX (FMA effect)", TQuery::TriTri, Variant::Avx2Fma, Variant::Avx),
        ("scalar SoA vs scalar AoS (layout)", TQuery::TriTri, Variant::Soa, Variant::Scalar),
        ("PQP vs brute force (AVX2+FMA)", TQuery::TriTri, Variant::Avx2Fma, Variant::Avx2Fma),
    ];
    for (label, q, x, y) in comps {
        let row = |p| {
            if label.starts_with("PQP") {
                ratio(qps(&thr, rw, q, x, p), qps(&thr, rw, TQuery::Brute, y, p))
            } else {
                ratio(qps(&thr, rw, q, x, p), qps(&thr, rw, q, y, p))
            }
        };
        let _ = writeln!(t, "| {label} | {} | {} |", row("f32"), row("f64"));
    }
    let wf = "Armadillo vs Armadillo, random triangles";
    let _ = writeln!(
        t,
        "| within-margin 0.02 vs full query, mostly far pairs ({wf}, {}) | {} | {} |",
        best_simd().name(),
        ratio(
            qps(&thr, wf, TQuery::Within, best_simd(), "f32"),
            qps(&thr, wf, TQuery::TriTri, best_simd(), "f32")
        ),
        ratio(
            qps(&thr, wf, TQuery::Within, best_simd(), "f64"),
            qps(&thr, wf, TQuery::TriTri, best_simd(), "f64")
        )
    );
    let _ = writeln!(
        t,
        "| f32 vs f64 ({}, tri-tri) | {} | |",
        best_simd().name(),
        ratio(
            qps(&thr, rw, TQuery::TriTri, best_simd(), "f32"),
            qps(&thr, rw, TQuery::TriTri, best_simd(), "f64")
        )
    );
    let peer_q = |wl: &str, p: &str| peer_qps(&peer_thr, wl, p);
    let _ = writeln!(
        t,
        "| {} tri-tri vs parry3d (same pairs) | {} | {} |",
        best_simd().name(),
        ratio(qps(&thr, rw, TQuery::TriTri, best_simd(), "f32"), peer_q(rw, "f32")),
        ratio(qps(&thr, rw, TQuery::TriTri, best_simd(), "f64"), peer_q(rw, "f64"))
    );
    let _ = writeln!(t, "\n## Peer: parry3d on the same inputs\n\nTriangle distance, million queries per second, one thread: parry3d (f32) and parry3d-f64 `query::distance` on `Triangle` shapes at identity poses, timed like the kernels on the same pairs in the same run, after checking that its distances agree with tridist's within 1e-3 S on at least 90% of the pairs (S: the pair's largest coordinate; the last column is what that check measured). Its accuracy against the oracle: [ACCURACY.md](ACCURACY.md#peer-parry3d--parry3d-f64-against-the-same-oracle).\n\n| workload | prec | tridist scalar (AoS) | tridist {} | parry3d | {} vs parry3d | parry: max abs(d - d')/S, pairs beyond 1e-3 |\n|---|---|---|---|---|---|---|", best_simd().name(), best_simd().name());
    for r in &peer_thr {
        let ours = qps(&thr, &r.workload, TQuery::TriTri, best_simd(), r.precision);
        let (pq, agree) = match &r.measured {
            Ok((q, worst, beyond)) => (Some(*q), format!("{worst:.1e}, {beyond}")),
            Err(e) => (None, format!("check failed: {e}")),
        };
        let _ = writeln!(
            t,
            "| {} | {} | {} | {} | {} | {} | {agree} |",
            r.workload,
            r.precision,
            mq(qps(&thr, &r.workload, TQuery::TriTri, Variant::Scalar, r.precision)),
            mq(ours),
            mq(pq),
            ratio(ours, pq)
        );
    }
    let failed: Vec<&TRow> = thr.iter().filter(|r| r.qps.is_err()).collect();
    if !failed.is_empty() {
        let _ = writeln!(t, "\n## Result checks that failed\n");
        for r in &failed {
            let _ = writeln!(
                t,
                "- {} {} {} {}: {}",
                r.workload,
                r.query.name(),
                r.variant.name(),
                r.precision,
                r.qps.clone().err().unwrap_or_default()
            );
        }
    }
    let _ = writeln!(t, "\nMachine-readable: [throughput.csv](throughput.csv) (read by `tridist advise`). The Stanford Armadillo is courtesy of the Stanford Computer Graphics Laboratory.");
    write_file(&s.out_dir, "THROUGHPUT.md", &t)?;
    write_file(&s.out_dir, "throughput.csv", &csv)?;

    // ---------- TRADEOFF.md + plots ----------
    let mut series = Vec::new();
    for (q, qn) in [(Query::TriTri, "pqp"), (Query::TriTriBrute, "brute")] {
        for p in ["f32", "f64"] {
            let mut labels = Vec::new();
            let pts: Vec<(f64, f64)> = Variant::ALL
                .iter()
                .filter_map(|&v| {
                    let tq = if q == Query::TriTri { TQuery::TriTri } else { TQuery::Brute };
                    let x = qps(&thr, rw, tq, v, p)? / 1e6;
                    let y = acc
                        .iter()
                        .filter(|r| r.query == q && r.variant == v && r.precision == p)
                        .map(|r| r.stats.max_excess)
                        .fold(0.0, f64::max);
                    labels.push(v.name().to_string());
                    Some((x, y.max(1e-3)))
                })
                .collect();
            series.push(Series { label: format!("{qn} {p}"), points: pts, line: false, labels });
        }
    }
    let trade = Plot {
        title: "Triangle-triangle: throughput vs worst-family error".into(),
        xlabel: "million queries/s (random unit-cube pairs, 1 thread)".into(),
        ylabel: "max excess E over all families".into(),
        xlog: true,
        ylog: true,
        series,
        hline: Some((8.0, "target E = 8".into())),
    };
    write_file(&s.out_dir, "tradeoff.svg", &trade.render())?;
    let magp = Plot {
        title: "Stability vs magnitude (tri-tri, scale family)".into(),
        xlabel: "largest coordinate S".into(),
        ylabel: "max excess E per decade".into(),
        xlog: true,
        ylog: true,
        series: mag,
        hline: Some((8.0, "target".into())),
    };
    write_file(&s.out_dir, "magnitude.svg", &magp.render())?;
    let offp = Plot {
        title: "Stability vs offset from origin (tri-tri, far family)".into(),
        xlabel: "offset (largest coordinate S)".into(),
        ylabel: "max excess E per decade".into(),
        xlog: true,
        ylog: true,
        series: off,
        hline: Some((8.0, "target".into())),
    };
    write_file(&s.out_dir, "offset.svg", &offp.render())?;
    let mut tr = header("Speed for accuracy: what each variant costs and what it buys", &s.command, seed);
    let _ = writeln!(tr, "Each point is one kernel variant and precision: its triangle-triangle throughput on random unit-cube pairs against its worst excess E over every input family. Lower right is better; anything under the dashed line meets the E <= 8 target on every family.\n\n![throughput vs error](tradeoff.svg)\n");
    let _ = writeln!(tr, "## Per family (max excess E, triangle-triangle PQP)\n\n| variant | prec | Mq/s | {} |\n|---|---|---|{}", Family::ALL.iter().map(|f| f.name()).collect::<Vec<_>>().join(" | "), "---|".repeat(Family::ALL.len()));
    for v in Variant::ALL {
        for p in ["f32", "f64"] {
            let cells: Vec<String> = Family::ALL
                .iter()
                .map(|&f| {
                    acc.iter()
                        .find(|r| {
                            r.query == Query::TriTri && r.variant == v && r.precision == p && r.family == f
                        })
                        .map(|r| fmt(r.stats.max_excess))
                        .unwrap_or_else(|| "-".into())
                })
                .collect();
            if cells.iter().all(|c| c == "-") {
                continue;
            }
            let _ = writeln!(
                tr,
                "| {} | {p} | {} | {} |",
                v.name(),
                mq(qps(&thr, rw, TQuery::TriTri, v, p)),
                cells.join(" | ")
            );
        }
    }
    let _ = writeln!(tr, "\n## Stability at the extremes\n\nEvery query scales its input by a power of two before computing, so the error relative to the magnitude stays flat from tiny to huge coordinates and far from the origin. Decades whose worst excess is below 1e-3 (for f32 below about 1e-19 the squared distance underflows to the correctly rounded 0, excess 0) are drawn at 1e-3.\n\n![error vs magnitude](magnitude.svg)\n\n![error vs offset](offset.svg)\n\n## Penalty method: iterations against error and time\n");
    let _ = writeln!(tr, "Krestenitis & Koziara's penalty method on random unit-cube pairs ({} cases), {} variant, default rho and regularisation, tolerance 0 so that every pair runs exactly `max_iter` steps. E is the excess error of the returned (feasible) points; time per query from one timed pass.\n\n![penalty iterations](penalty.svg)\n\n| precision | max_iter | median E | p99 E | max E | Mq/s |\n|---|---|---|---|---|---|", s.cases * 2, simd.name());
    let mut pen_series = Vec::new();
    for p in ["f32", "f64"] {
        let rows = if p == "f32" {
            penalty_sweep::<f32>(simd, s.cases * 2)
        } else {
            penalty_sweep::<f64>(simd, s.cases * 2)
        };
        for (it, med, p99, mx, q) in &rows {
            let _ = writeln!(
                tr,
                "| {p} | {it} | {} | {} | {} | {:.2} |",
                fmt(*med),
                fmt(*p99),
                fmt(*mx),
                q / 1e6
            );
        }
        let curve = |e: fn(&(u32, f64, f64, f64, f64)) -> f64| -> Vec<(f64, f64)> {
            rows.iter().map(|r| (r.0 as f64, e(r).max(1e-3))).collect()
        };
        pen_series.push(Series::line(format!("median E {p}"), curve(|r| r.1)));
        pen_series.push(Series::line(format!("p99 E {p}"), curve(|r| r.2)));
    }
    let penp = Plot {
        title: "Penalty method: error vs iterations (random unit-cube pairs)".into(),
        xlabel: "Newton iterations (max_iter, tol = 0)".into(),
        ylabel: "excess E".into(),
        xlog: true,
        ylog: true,
        series: pen_series,
        hline: Some((8.0, "target".into())),
    };
    write_file(&s.out_dir, "penalty.svg", &penp.render())?;
    write_file(&s.out_dir, "TRADEOFF.md", &tr)?;
    prog.step("writing reports");

    if let Some(readme) = &s.readme {
        update_readme(readme, &acc, &thr, &peer_acc, &peer_thr)?;
    }
    prog.step("README results");
    if !failed.is_empty() {
        return Err(format!("{} throughput result check(s) failed; see THROUGHPUT.md", failed.len()));
    }
    Ok(())
}

fn update_readme(
    path: &Path,
    acc: &[Row],
    thr: &[TRow],
    peer_acc: &[(Family, &'static str, Stats)],
    peer_thr: &[PeerRow],
) -> Result<(), String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let (b, e) = ("<!-- results:begin -->", "<!-- results:end -->");
    let (Some(i), Some(j)) = (text.find(b), text.find(e)) else { return Ok(()) };
    let rw = "random unit cube";
    let exact_kernels = acc.iter().filter(|r| r.query != Query::Penalty);
    let maxe = exact_kernels.clone().map(|r| r.stats.max_excess).fold(0.0, f64::max);
    let mis: usize =
        exact_kernels.map(|r| r.stats.contact_misses + r.stats.false_zeros + r.stats.nonfinite).sum();
    let pen: Vec<&Row> = acc.iter().filter(|r| r.query == Query::Penalty).collect();
    let pen_med = pen.iter().map(|r| r.stats.median).fold(0.0, f64::max);
    let pen_max = pen.iter().map(|r| r.stats.max_excess).fold(0.0, f64::max);
    let simd = best_simd();
    let q = |v, p| qps(thr, rw, TQuery::TriTri, v, p);
    let r = |x: Option<f64>, y: Option<f64>| match (x, y) {
        (Some(a), Some(b)) => format!("{:.1}x", a / b),
        _ => "-".into(),
    };
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{b}\n_Generated by `tridist report`; numbers from the last run on {}._\n",
        crate::common::machine()
    );
    let _ = writeln!(s, "- Worst excess error of the exact-method kernels (segment-segment, point-triangle, triangle-triangle PQP and brute force, intersection) over every variant, precision and input family: **E = {}** (target 8); contact misses + false zeros + non-finite outputs: **{mis}**.", fmt(maxe));
    let _ = writeln!(s, "- The penalty method (an approximation, default options): median E at most {} on every family, worst case {}.", fmt(pen_med), fmt(pen_max));
    let _ = writeln!(s, "- Triangle-triangle on random unit-cube pairs, f32: {} {} M/s vs scalar {} M/s (**{}**); f64: {} M/s vs {} M/s (**{}**).", simd.name(), q(simd, "f32").map(|v| format!("{:.1}", v / 1e6)).unwrap_or_default(), q(Variant::Scalar, "f32").map(|v| format!("{:.2}", v / 1e6)).unwrap_or_default(), r(q(simd, "f32"), q(Variant::Scalar, "f32")), q(simd, "f64").map(|v| format!("{:.1}", v / 1e6)).unwrap_or_default(), q(Variant::Scalar, "f64").map(|v| format!("{:.2}", v / 1e6)).unwrap_or_default(), r(q(simd, "f64"), q(Variant::Scalar, "f64")));
    let peer_q = |p: &str| peer_qps(peer_thr, rw, p);
    let peer_e = |p: &str| peer_acc.iter().filter(|x| x.1 == p).map(|x| x.2.max_excess).fold(0.0, f64::max);
    let peer_mis = |p: &str| -> usize {
        peer_acc
            .iter()
            .filter(|x| x.1 == p)
            .map(|x| x.2.contact_misses + x.2.false_zeros + x.2.nonfinite)
            .sum()
    };
    let _ = writeln!(s, "- The peer, parry3d `query::distance` on the same random pairs: f32 {} M/s ({} is **{}** faster), f64 {} M/s (**{}**); its worst E over the families: {} (f32), {} (f64), with {} / {} contact misses + false zeros + non-finite outputs.", peer_q("f32").map(|v| format!("{:.2}", v / 1e6)).unwrap_or_default(), simd.name(), r(q(simd, "f32"), peer_q("f32")), peer_q("f64").map(|v| format!("{:.2}", v / 1e6)).unwrap_or_default(), r(q(simd, "f64"), peer_q("f64")), fmt(peer_e("f32")), fmt(peer_e("f64")), peer_mis("f32"), peer_mis("f64"));
    let _ = writeln!(s, "\n![throughput vs error](reports/tradeoff.svg)\n\nFull tables: [reports/ACCURACY.md](reports/ACCURACY.md), [reports/THROUGHPUT.md](reports/THROUGHPUT.md), [reports/TRADEOFF.md](reports/TRADEOFF.md).");
    let out = format!("{}{}{}", &text[..i], s, &text[j..]);
    std::fs::write(path, out).map_err(|e| format!("{}: {e}", path.display()))
}
