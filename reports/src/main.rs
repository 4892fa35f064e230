//! The `tridist` command: regenerate the reports, evaluate pairs from stdin with any kernel of
//! the registry (or the exact oracle), time a file of pairs (or a peer on it), and advise a
//! variant for a scene.
//!
//! Exit status: 0 success (also when standard output closes early, as with `| head`); 1 the run completed with a negative answer (malformed input lines
//! were skipped, `advise` found no variant that meets the tolerance); 2 usage error (unknown
//! subcommand, flag or value; printed with the usage); 3 runtime error (a file that cannot be
//! read, an empty input, a variant this CPU lacks, a failed result check).

#[macro_use]
mod common;
mod judge;
mod meshcases;
mod meshcmd;
mod meshprotocol;
mod meshreport;
mod peers;
mod plot;
mod posescmd;
mod report;
mod table;

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use clap::{Args, Parser, Subcommand, ValueEnum};
use tridist::{Engine, Interval, PenaltyOptions, Query, Tolerance};
use tridist_scenes::bounds::bound_any_family;
use tridist_scenes::eval::{
    parse_case_line_exact, prims, run_with, run_with_distances, summarise, truth, Variant,
};
use tridist_scenes::float::Float;
use tridist_scenes::peer::{self, Lib};
use tridist_scenes::Case;

/// Fast triangle distance kernels, measured: how fast, and how wrong, on every kind of input.
#[derive(Parser, Debug)]
#[command(name = "tridist", version, after_help = EXIT_CODES)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

const EXIT_CODES: &str = "Exit status: 0 success (also when standard output is closed early, as by `| head`); 1 completed with a negative answer (malformed input lines skipped, no variant meets the tolerance); 2 usage error; 3 runtime error (unreadable file, empty input, unavailable variant, failed result check).";

#[derive(Subcommand, Debug)]
enum Cmd {
    /// Regenerate the accuracy and throughput reports and plots.
    ///
    /// Accuracy sweep against the exact oracle, throughput (with the peers on the same pairs)
    /// and plots into reports/ (ACCURACY.md, THROUGHPUT.md, TRADEOFF.md, *.svg,
    /// throughput.csv) and the README's results section.
    Report {
        /// Fewer cases and pairs, shorter timing (two to three minutes on 2 cores, plus the build).
        #[arg(long)]
        quick: bool,
        /// Write here instead of reports/ (the README is then left alone).
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Cases per query, family and precision [default: 1500, --quick 150].
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..), allow_negative_numbers = true)]
        cases: Option<u32>,
        /// Pairs per throughput workload [default: 20000, --quick 4000].
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..), allow_negative_numbers = true)]
        pairs: Option<u32>,
        /// Time budget per throughput measurement in milliseconds [default: 400, --quick 60].
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..), allow_negative_numbers = true)]
        budget_ms: Option<u32>,
        /// Poses of the mesh trajectory (MESH.md) [default: 12; 2 = the two ends only].
        #[arg(long, value_parser = clap::value_parser!(u32).range(2..=1000), allow_negative_numbers = true)]
        mesh_poses: Option<u32>,
        /// Largest subdivision of the mesh report's scale section: 0 the Armadillo's 52,000
        /// triangles per mesh only, 1 up to 208,000, 2 up to 832,000 [default: 2].
        #[arg(long, value_parser = clap::value_parser!(u32).range(0..=2), allow_negative_numbers = true)]
        mesh_scale: Option<u32>,
    },
    /// Answer the pairs on stdin with any kernel, or the exact oracle.
    ///
    /// Reads pairs from stdin (a label and 18 coordinates per line: triangle A then B, then
    /// optionally `exact=NUM/DEN`, ignored, as `tridist cases --exact` writes; blank and #
    /// lines ignored) and prints `label answer` per pair. Segment queries use the first
    /// edge (vertices 0-1) of each triangle, point-triangle vertex 0 of B against A. Answers:
    /// the squared distance (shortest round-trip decimal; within-margin prints `inf` beyond
    /// the margin), or `intersecting` / `disjoint` / `invalid`.
    Eval(EvalArgs),
    /// Time a kernel (or a peer) on the pairs in a file.
    ///
    /// Times a batch query over the pairs in a file (same format as eval): queries per second,
    /// the median of repeated passes, and where the pairs went.
    Bench(BenchArgs),
    /// Write the input families as a case file (optionally with exact answers).
    ///
    /// The pairs every test and report uses, reproducibly (same seed, same bytes), in the
    /// format eval, bench and judge read: a label and 18 coordinates per line.
    Cases(judge::CasesArgs),
    /// Judge another implementation's answers to a case file against the exact oracle.
    ///
    /// Reads the cases and one answer per case (squared distance, optionally the closest
    /// points; `nan`, `inf`, `error` allowed; verdict words for intersect) and prints the
    /// per-family table of the reports. Exit status 1 when a limit is exceeded, 3 on a
    /// malformed or misaligned file (with its line number). With --mesh, mesh case files
    /// (`tridist mesh-cases`) and their answers.
    Judge(judge::JudgeArgs),
    /// Judge every peer built in, and tridist, on the committed corpus: reports/PEERS.md.
    ///
    /// The conformance table: each library's triangle distance, in each precision and
    /// configuration it offers, answers corpus/ (the input families with exact answers, and
    /// bad input), judged against the exact answers; every failure named by file and line.
    Peers(peers::PeersArgs),
    /// Write the conformance corpus's mesh scenes with their exact answers (corpus/mesh).
    ///
    /// The meshes as OFF and one placed pair per line with the smallest exact squared
    /// distance of the exactly placed meshes and a triangle pair attaining it (corpus/README.md).
    MeshCases(meshcases::MeshCasesArgs),
    /// Answer a mesh case file with tridist or a mesh peer (for `tridist judge --mesh`).
    ///
    /// Prints `label squared-distance [triangle pair]` per case (`error` when there is none).
    MeshEval(meshcases::MeshEvalArgs),
    /// Distance, intersection, contacts and closest point of two meshes (OFF) in poses.
    ///
    /// Builds each mesh's tree once and runs the mesh queries, the batch kernels doing the
    /// leaf work: prints the distance, closest points and the triangle pair, whether they
    /// intersect, with --margin the contact count and the closest contacts, with --point the
    /// closest point of the second mesh.
    Mesh(meshcmd::MeshArgs),
    /// Write the poses of one of the report's mesh protocols for two meshes.
    ///
    /// Both meshes normalised to [-1, 1]^3 as the report places them; one pose of the second
    /// mesh per line (a label, the translation and the rotation's rows), for `tridist mesh A B
    /// --normalise --poses FILE`.
    Poses(posescmd::PosesArgs),
    /// Pick the fastest variant that meets a distance tolerance.
    ///
    /// Picks the fastest variant whose declared error bound (the bound table's E, times u S)
    /// meets an absolute distance tolerance at coordinate magnitude S, from throughput.csv.
    Advise {
        /// Largest absolute coordinate S of the scene.
        #[arg(long, value_parser = positive, allow_hyphen_values = true)]
        scale: f64,
        /// Largest acceptable distance error, in the scene's units.
        #[arg(long, value_parser = positive, allow_hyphen_values = true)]
        tolerance: f64,
        /// The query (registry name).
        #[arg(long, default_value = "tri_tri", value_parser = parse_query)]
        query: Query,
        /// The throughput table to read [default: reports/throughput.csv].
        #[arg(long, value_name = "FILE")]
        csv: Option<PathBuf>,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum Prec {
    F32,
    F64,
}

#[derive(Args, Debug)]
struct KernelArgs {
    // The help lists the registry's queries (kernel_help), so a new query appears by itself.
    #[arg(long, default_value = "tri_tri", value_parser = parse_kernel, help = kernel_help())]
    kernel: Kernel,
    /// The query whose exact answer `--kernel oracle` prints.
    #[arg(long, default_value = "tri_tri", value_parser = parse_query)]
    query: Query,
    /// Instruction set and layout (`auto`: the best this CPU runs, or the one `TRIDIST_ISA`
    /// names).
    #[arg(long, default_value = "auto", value_parser = parse_variant)]
    variant: Variant,
    /// Input and working precision.
    #[arg(long, value_enum, default_value = "f64")]
    precision: Prec,
    /// Certified-interval tolerance: `default` (64 u S), `exact`, `K` or `scaled:K` (K u S),
    /// `abs:X`, `rel:R`, or a comma-separated combination (the widest applies); or
    /// `correctly-rounded` (every squared distance the exact one rounded to nearest, or the
    /// pair counted undecided).
    #[arg(long, default_value = "default", value_parser = parse_tolerance, allow_hyphen_values = true)]
    tolerance: Tolerance,
    /// Threads (0: every core).
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    threads: usize,
    /// Margin of the within-margin query (required for it).
    #[arg(long, value_parser = non_negative, allow_hyphen_values = true)]
    margin: Option<f64>,
    /// Penalty method: iteration limit.
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    penalty_iters: Option<u32>,
    /// Penalty method: stop when the step is below this times S.
    #[arg(long, value_name = "X", value_parser = positive, allow_hyphen_values = true)]
    penalty_tol: Option<f64>,
}

#[derive(Args, Debug)]
struct EvalArgs {
    #[command(flatten)]
    k: KernelArgs,
    /// With `--kernel oracle`: print the exact squared distance as a fraction.
    #[arg(long)]
    exact: bool,
    /// Append the distance (not squared) after the square: its square root, except under
    /// `--tolerance correctly-rounded`, where it is the exact distance correctly rounded,
    /// decided on its own (with `--kernel oracle`: that value).
    #[arg(long)]
    distances: bool,
    /// Append the certified interval `[lo, hi]` of the distance (not squared).
    #[arg(long)]
    intervals: bool,
    /// Append the excess error E against the exact oracle (verdicts: ok / misjudged).
    #[arg(long)]
    check: bool,
    /// Append the closest points `px py pz qx qy qz` (distance queries).
    #[arg(long)]
    points: bool,
    /// Answer with a peer's triangle-triangle distance instead (parry3d, fcl, coal, trueform),
    /// squared in the input precision.
    #[arg(long, value_parser = parse_peer)]
    peer: Option<Lib>,
    /// List every kernel, variant and precision this CPU runs, then exit.
    #[arg(long)]
    list: bool,
}

#[derive(Args, Debug)]
struct BenchArgs {
    /// The pairs to time.
    #[arg(long, value_name = "FILE")]
    input: PathBuf,
    #[command(flatten)]
    k: KernelArgs,
    /// Timed passes (after one warm-up).
    #[arg(
        long,
        default_value_t = 11,
        value_parser = clap::value_parser!(u32).range(1..),
        allow_negative_numbers = true,
    )]
    reps: u32,
    /// Time a peer's triangle-triangle distance on the same pairs instead (parry3d, fcl; coal and
    /// trueform are judged only).
    #[arg(long, value_parser = parse_peer)]
    peer: Option<Lib>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Kernel {
    Query(Query),
    Oracle,
}

/// `--kernel`'s help, from the registry.
fn kernel_help() -> String {
    let names: Vec<&str> = Query::ALL.iter().map(|q| q.name()).collect();
    format!(
        "Query of the registry ({}; `pqp` and `brute` name the triangle-triangle ones) or `oracle` (the exact answer of --query)",
        names.join(", ")
    )
}

fn parse_kernel(s: &str) -> Result<Kernel, String> {
    match s {
        "oracle" => Ok(Kernel::Oracle),
        "pqp" => Ok(Kernel::Query(Query::TriTri)),
        "brute" => Ok(Kernel::Query(Query::TriTriBrute)),
        _ => parse_query(s).map(Kernel::Query),
    }
}

fn parse_query(s: &str) -> Result<Query, String> {
    Query::parse(s).ok_or_else(|| {
        let names: Vec<&str> = Query::ALL.iter().map(|q| q.name()).collect();
        format!("unknown query (one of {})", names.join(", "))
    })
}

pub(crate) fn parse_variant(s: &str) -> Result<Variant, String> {
    if s == "auto" {
        // (a run under valgrind with TRIDIST_ISA=avx2fma must not meet AVX-512)
        return Variant::auto().map_err(|e| format!("{}: {e}", tridist::ISA_ENV));
    }
    Variant::parse(s)
        .ok_or_else(|| "unknown variant (scalar, soa, sse41, avx, avx2fma, avx512vl, avx512, auto)".into())
}

fn parse_peer(s: &str) -> Result<Lib, String> {
    Lib::JUDGED
        .into_iter()
        .find(|l| l.name() == s)
        .ok_or_else(|| "unknown peer (parry3d, fcl, coal, trueform)".into())
}

fn positive(s: &str) -> Result<f64, String> {
    s.parse::<f64>()
        .ok()
        .filter(|x| x.is_finite() && *x > 0.0)
        .ok_or_else(|| "needs a positive finite number".into())
}

fn non_negative(s: &str) -> Result<f64, String> {
    s.parse::<f64>()
        .ok()
        .filter(|x| x.is_finite() && *x >= 0.0)
        .ok_or_else(|| "needs a finite number >= 0".into())
}

pub(crate) fn parse_tolerance(s: &str) -> Result<Tolerance, String> {
    match s {
        "default" => return Ok(Tolerance::DEFAULT),
        "exact" => return Ok(Tolerance::EXACT),
        "correctly-rounded" => return Ok(Tolerance::CORRECTLY_ROUNDED),
        _ => {}
    }
    let mut t = Tolerance::EXACT;
    for part in s.split(',') {
        let (k, v) = part.split_once(':').unwrap_or(("scaled", part));
        let x = non_negative(v).map_err(|e| format!("{part:?}: {e}"))?;
        match k {
            "scaled" => t.scaled = x,
            "abs" => t.absolute = x,
            "rel" => t.relative = x,
            _ => return Err(format!("{part:?}: expected scaled:K, abs:X or rel:R")),
        }
    }
    Ok(t)
}

/// A runtime failure (exit status 3).
pub(crate) struct Fail(pub(crate) String);

impl<E: std::fmt::Display> From<E> for Fail {
    fn from(e: E) -> Self {
        Fail(e.to_string())
    }
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let _ = e.print();
            return ExitCode::from(e.exit_code().clamp(0, 255) as u8);
        }
    };
    let res = match cli.cmd {
        Cmd::Report { quick, out, cases, pairs, budget_ms, mesh_poses, mesh_scale } => {
            cmd_report(quick, out, cases, pairs, budget_ms, mesh_poses, mesh_scale)
        }
        Cmd::Eval(a) => cmd_eval(&a),
        Cmd::Bench(a) => cmd_bench(&a),
        Cmd::Cases(a) => judge::cmd_cases(&a),
        Cmd::Judge(a) => judge::cmd_judge(&a),
        Cmd::Peers(a) => peers::cmd_peers(&a),
        Cmd::MeshCases(a) => meshcases::cmd_mesh_cases(&a),
        Cmd::MeshEval(a) => meshcases::cmd_mesh_eval(&a),
        Cmd::Mesh(a) => meshcmd::cmd_mesh(&a),
        Cmd::Poses(a) => posescmd::cmd_poses(&a),
        Cmd::Advise { scale, tolerance, query, csv } => cmd_advise(scale, tolerance, query, csv),
    };
    match res {
        Ok(c) => c,
        Err(Fail(e)) => {
            eprintln!("tridist: error: {e}");
            ExitCode::from(3)
        }
    }
}

/// The repository root (the reports' home).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().map_or_else(|| PathBuf::from("."), Path::to_path_buf)
}

fn cmd_report(
    quick: bool,
    out: Option<PathBuf>,
    cases: Option<u32>,
    pairs: Option<u32>,
    budget_ms: Option<u32>,
    mesh_poses: Option<u32>,
    mesh_scale: Option<u32>,
) -> Result<ExitCode, Fail> {
    let pick = |x: Option<u32>, q: u32, full: u32| x.unwrap_or(if quick { q } else { full });
    // the opt-in variants are measured only in a build that compiled them
    let features = if cfg!(feature = "all-variants") { " --features all-variants" } else { "" };
    let mut command = format!(
        "cargo run --release -p tridist-reports{features} -- report{}",
        if quick { " --quick" } else { "" }
    );
    for (k, v) in [
        ("--cases", cases),
        ("--pairs", pairs),
        ("--budget-ms", budget_ms),
        ("--mesh-poses", mesh_poses),
        ("--mesh-scale", mesh_scale),
    ] {
        if let Some(v) = v {
            command.push_str(&format!(" {k} {v}"));
        }
    }
    let s = report::Settings {
        cases: pick(cases, 150, 1500) as usize,
        pairs: pick(pairs, 4000, 20_000) as usize,
        budget: Duration::from_millis(pick(budget_ms, 60, 400).into()),
        mesh_poses: mesh_poses.unwrap_or(12) as usize,
        mesh_scale: mesh_scale.unwrap_or(2),
        command,
        readme: out.is_none().then(|| root().join("README.md")),
        out_dir: out.unwrap_or_else(|| root().join("reports")),
    };
    report::run_report(&s).map_err(Fail)?;
    eprintln!("wrote the reports to {}", s.out_dir.display());
    Ok(ExitCode::SUCCESS)
}

/// The engine of the kernel arguments.
fn engine<T: Float>(k: &KernelArgs, q: Query) -> Result<Engine, Fail> {
    if !k.variant.available() {
        return Err(Fail(format!("variant {} is not available on this CPU", k.variant.name())));
    }
    let mut e = Engine::new(k.variant.isa())?.threads(k.threads).tolerance(k.tolerance);
    if q == Query::Within {
        let m = k.margin.ok_or_else(|| Fail("the within query needs --margin".into()))?;
        e = e.margin(m);
    }
    if q == Query::Penalty {
        let mut o = PenaltyOptions::<T>::default();
        if let Some(n) = k.penalty_iters {
            o.max_iter = n;
        }
        if let Some(x) = k.penalty_tol {
            o.tol = T::from_f64(x);
        }
        e = e.penalty(&o);
    }
    // the setters never fail: say what is wrong before any input is read
    e.check()?;
    Ok(e)
}

/// Reads case lines; returns the parsed cases and the parse errors (with line numbers).
fn read_cases<T: Float>(text: &str) -> (Vec<Case<T>>, Vec<String>) {
    let mut cases = Vec::new();
    let mut errors = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let l = line.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        // a trailing `exact=NUM/DEN` (`tridist cases --exact`) is read and ignored
        match parse_case_line_exact::<T>(l) {
            Ok((c, _)) => cases.push(c),
            Err(e) => errors.push(format!("line {}: {e}", i + 1)),
        }
    }
    (cases, errors)
}

fn cmd_eval(a: &EvalArgs) -> Result<ExitCode, Fail> {
    if a.list {
        for &q in Query::ALL {
            for v in Variant::ALL.iter().filter(|v| v.available()) {
                for p in ["f32", "f64"] {
                    outln!("{} {} {p}", q.name(), v.name());
                }
            }
        }
        outln!("oracle exact f32\noracle exact f64");
        return Ok(ExitCode::SUCCESS);
    }
    if a.peer.is_some() && (a.k.kernel == Kernel::Oracle || a.check || a.intervals || a.points || a.distances)
    {
        return Err(Fail(
            "--peer prints the peer's squared distance only (no oracle, --check, --distances, --intervals or --points)"
                .into(),
        ));
    }
    if a.distances && a.exact {
        return Err(Fail("--exact prints the oracle's fraction of the square: not with --distances".into()));
    }
    if a.exact && a.k.kernel != Kernel::Oracle {
        return Err(Fail("--exact prints the oracle's fraction: use it with --kernel oracle".into()));
    }
    let mut text = String::new();
    std::io::stdin().read_to_string(&mut text).map_err(|e| Fail(format!("reading stdin: {e}")))?;
    match a.k.precision {
        Prec::F32 => eval_as::<f32>(&text, a),
        Prec::F64 => eval_as::<f64>(&text, a),
    }
}

fn verdict_word(d2_is_zero: bool) -> &'static str {
    if d2_is_zero {
        "intersecting"
    } else {
        "disjoint"
    }
}

fn eval_as<T: peer::Peer>(text: &str, a: &EvalArgs) -> Result<ExitCode, Fail> {
    let (cases, errors) = read_cases::<T>(text);
    for e in &errors {
        eprintln!("tridist eval: {e}");
    }
    let q = match a.k.kernel {
        Kernel::Query(q) => q,
        Kernel::Oracle => a.k.query,
    };
    let e = engine::<T>(&a.k, q)?;
    let lines = if let Some(lib) = a.peer {
        peer_lines(lib, q, &cases)?
    } else if a.k.kernel == Kernel::Oracle {
        oracle_lines(q, &cases, a)?
    } else {
        kernel_lines(e, q, &cases, a)?
    };
    for (c, l) in cases.iter().zip(lines) {
        outln!("{} {l}", c.label);
    }
    Ok(if errors.is_empty() { ExitCode::SUCCESS } else { ExitCode::from(1) })
}

/// A peer's squared triangle-triangle distances (its distance squared in `T`, as the report's
/// peer table judges them).
fn peer_lines<T: peer::Peer>(lib: Lib, q: Query, cases: &[Case<T>]) -> Result<Vec<String>, Fail> {
    if q != Query::TriTri {
        return Err(Fail("--peer answers the triangle-triangle distance (--kernel tri_tri) only".into()));
    }
    if !lib.available() {
        return Err(Fail(format!("{} is not built in: {}", lib.name(), lib.missing_reason())));
    }
    if !lib.offers::<T>() {
        return Err(Fail(format!(
            "{} does not compute in {} (its library is built for double)",
            lib.name(),
            T::NAME
        )));
    }
    let ta: Vec<_> = cases.iter().map(|c| c.a).collect();
    let tb: Vec<_> = cases.iter().map(|c| c.b).collect();
    let mut d = vec![T::ZERO; cases.len()];
    peer::Shapes::for_lib(lib, &ta, &tb).distances(&mut d);
    Ok(d.iter().map(|&x| if x.is_nan() { "error".to_string() } else { format!("{:?}", x * x) }).collect())
}

fn oracle_lines<T: Float>(q: Query, cases: &[Case<T>], a: &EvalArgs) -> Result<Vec<String>, Fail> {
    let pr = tridist_scenes::eval::prec::<T>();
    let mut out = Vec::new();
    for c in cases {
        if !c.is_finite() {
            out.push("error: non-finite input".into());
            continue;
        }
        let t = &truth(q, std::slice::from_ref(c))[0];
        let line = if q.is_verdict() {
            verdict_word(t.d2 == 0).to_string()
        } else if a.exact {
            format!("{}/{}", t.d2.numer(), t.d2.denom())
        } else {
            let r = T::from_f64(pr.round(&t.d2));
            if q == Query::Within
                && a.k.margin.is_some_and(|m| t.d2 > rug::Rational::from_f64(m * m).unwrap_or_default())
            {
                if a.distances { "inf inf" } else { "inf" }.to_string()
            } else if a.distances {
                format!("{r:?} {:?}", tridist_scenes::eval::rn_sqrt::<T>(&t.d2))
            } else {
                format!("{r:?}")
            }
        };
        out.push(line);
    }
    Ok(out)
}

fn kernel_lines<T: Float>(e: Engine, q: Query, cases: &[Case<T>], a: &EvalArgs) -> Result<Vec<String>, Fail> {
    let ms = a.k.margin.map(|m| vec![T::from_f64(m); cases.len()]);
    let out = if a.distances && !q.is_verdict() {
        run_with_distances(e, q, a.k.variant, cases, ms.as_deref())?
    } else {
        run_with(e, q, a.k.variant, cases, ms.as_deref())?
    };
    let judged = a.check.then(|| {
        let tr = truth(q, cases);
        let b = bound_any_family(q, a.k.variant, T::NAME);
        let ms = a.k.margin.map(|m| vec![T::from_f64(m); cases.len()]);
        summarise(q, cases, &tr, &out, b.allow, ms.as_deref()).1
    });
    let mut lines = Vec::new();
    for i in 0..cases.len() {
        let mut l = if q.is_verdict() {
            match out.verdict[i].as_bool() {
                Some(v) => verdict_word(v).to_string(),
                None => "invalid".to_string(),
            }
        } else {
            let d = out.d[i];
            if d == T::INFINITY {
                "inf".to_string()
            } else {
                format!("{d:?}")
            }
        };
        if a.distances && !q.is_verdict() {
            let d = out.dist[i];
            l.push_str(&if d == T::INFINITY { " inf".to_string() } else { format!(" {d:?}") });
        }
        if a.points && !q.is_verdict() {
            for x in out.p[i].iter().chain(out.q[i].iter()) {
                l.push_str(&format!(" {x:?}"));
            }
        }
        if a.intervals && !q.is_verdict() {
            let Interval { lo, hi } = out.iv[i];
            l.push_str(&format!(" [{lo:?}, {hi:?}]"));
        }
        // an answer the correctly rounded mode could not decide is said to be so
        if e.current_tolerance().correctly_rounded
            && !q.is_verdict()
            && !out.certified[i]
            && !out.d[i].is_nan()
        {
            l.push_str(" undecided");
        }
        if let Some(js) = &judged {
            let j = &js[i];
            if !cases[i].is_finite() {
                l.push_str(" E=-");
            } else if q.is_verdict() {
                l.push_str(if j.misjudged { " misjudged" } else { " ok" });
            } else {
                l.push_str(&format!(" E={}", j.excess));
            }
        }
        lines.push(l);
    }
    Ok(lines)
}

fn cmd_bench(a: &BenchArgs) -> Result<ExitCode, Fail> {
    let text = std::fs::read_to_string(&a.input).map_err(|e| Fail(format!("{}: {e}", a.input.display())))?;
    if a.k.kernel == Kernel::Oracle {
        return Err(Fail("bench times the kernels, not the oracle".into()));
    }
    match a.k.precision {
        Prec::F32 => bench_as::<f32>(&text, a),
        Prec::F64 => bench_as::<f64>(&text, a),
    }
}

fn bench_as<T: peer::Peer>(text: &str, a: &BenchArgs) -> Result<ExitCode, Fail> {
    let (cases, errors) = read_cases::<T>(text);
    if !errors.is_empty() {
        return Err(Fail(format!("{} malformed line(s), first: {}", errors.len(), errors[0])));
    }
    if cases.is_empty() {
        return Err(Fail("no pairs in the input".into()));
    }
    let n = cases.len();
    let time = |f: &mut dyn FnMut()| -> f64 {
        f();
        let mut t: Vec<f64> = (0..a.reps)
            .map(|_| {
                let s = std::time::Instant::now();
                f();
                s.elapsed().as_secs_f64()
            })
            .collect();
        t.sort_by(|x, y| x.total_cmp(y));
        t[t.len() / 2]
    };
    if let Some(lib) = a.peer {
        if !Lib::ALL.contains(&lib) {
            return Err(Fail(format!(
                "{} answers triangle pairs through two one-triangle meshes: judged (eval), not timed",
                lib.name()
            )));
        }
        if !lib.available() {
            return Err(Fail(format!("{} is not built in: {}", lib.name(), lib.missing_reason())));
        }
        let ta: Vec<_> = cases.iter().map(|c| c.a).collect();
        let tb: Vec<_> = cases.iter().map(|c| c.b).collect();
        let (worst, beyond) = peer::agreement(lib, &ta, &tb).map_err(Fail)?;
        let shapes = peer::Shapes::for_lib(lib, &ta, &tb);
        let mut out = vec![T::ZERO; n];
        let secs = time(&mut || shapes.distances(&mut out));
        outln!(
            "{n} pairs, {} {}: {:.0} queries/s (median of {} passes after one warm-up)",
            lib.name(),
            T::NAME,
            n as f64 / secs,
            a.reps
        );
        outln!("agreement with tridist: max |d - d'| / S = {worst:.1e}, {beyond} pairs beyond 1e-3");
        return Ok(ExitCode::SUCCESS);
    }
    let Kernel::Query(q) = a.k.kernel else { unreachable!("checked by cmd_bench") };
    let e = engine::<T>(&a.k, q)?;
    let aos = a.k.variant == Variant::Scalar;
    let (ta, tb): (Vec<_>, Vec<_>) = cases.iter().map(|c| prims(q, c)).unzip();
    // every query reads its primitives from the first K points of each padded triple (prims)
    let (secs, counts) = match q.arity() {
        (2, 2) => {
            let sa: Vec<[tridist::Point<T>; 2]> = ta.iter().map(|t| [t[0], t[1]]).collect();
            let sb: Vec<[tridist::Point<T>; 2]> = tb.iter().map(|t| [t[0], t[1]]).collect();
            time_batch(e, q, &sa, &sb, aos, &time)?
        }
        (1, 3) => {
            let sa: Vec<[tridist::Point<T>; 1]> = ta.iter().map(|t| [t[0]]).collect();
            time_batch(e, q, &sa, &tb, aos, &time)?
        }
        _ => time_batch(e, q, &ta, &tb, aos, &time)?,
    };
    let c = counts;
    outln!(
        "{n} pairs, {} {} {}: {:.0} queries/s (median of {} passes after one warm-up, {} thread(s))",
        q.name(),
        a.k.variant.name(),
        T::NAME,
        n as f64 / secs,
        a.reps,
        e.thread_count()
    );
    outln!(
        "paths of one pass: prefiltered {}, delegated {}, refined {}, recertified {}, compacted {}, widened to f64 {}, exact {}, uncertified {}",
        c.prefiltered, c.delegated, c.refined, c.recertified, c.compacted, c.widened, c.exact, c.uncertified
    );
    if e.current_tolerance().correctly_rounded {
        // the correctly rounded mode's own paths
        outln!("correctly rounded: {} decided by a proof of contact, {} undecided", c.crossed, c.undecided);
    }
    Ok(ExitCode::SUCCESS)
}

/// Times one batch layout: SoA batches, or the slices themselves for the scalar AoS variant.
fn time_batch<T: Float, const KA: usize, const KB: usize>(
    e: Engine,
    q: Query,
    a: &[[tridist::Point<T>; KA]],
    b: &[[tridist::Point<T>; KB]],
    aos: bool,
    time: &dyn Fn(&mut dyn FnMut()) -> f64,
) -> Result<(f64, tridist::PathCounts), Fail> {
    let n = a.len();
    let (ba, bb) = (tridist::Batch::from_slice(a), tridist::Batch::from_slice(b));
    let (mut d, mut v) = (vec![T::ZERO; n], vec![tridist::Intersection::Invalid; n]);
    let mut res = Ok(tridist::PathCounts::default());
    let secs = time(&mut || {
        let o = if q.is_verdict() {
            tridist::Outputs::new().verdicts(&mut v)
        } else {
            tridist::Outputs::new().sqdist(&mut d)
        };
        res = if aos {
            e.run(q, tridist::Prims::Aos(a), tridist::Prims::Aos(b), o)
        } else {
            e.run(q, &ba, &bb, o)
        };
    });
    Ok((secs, res?))
}

fn cmd_advise(scale: f64, tol: f64, query: Query, csv: Option<PathBuf>) -> Result<ExitCode, Fail> {
    let path = csv.unwrap_or_else(|| root().join("reports/throughput.csv"));
    let rows = table::read(&path).map_err(|e| Fail(format!("{e} (run `tridist report` first)")))?;
    struct Opt {
        v: Variant,
        p: &'static str,
        e: f64,
        err: f64,
        qps: Option<f64>,
        /// It does not meet the tolerance (`Some`), with the reason when it is not the bound.
        why: Option<String>,
    }
    let mut options = Vec::new();
    for v in Variant::ALL.into_iter().filter(|v| v.available()) {
        for (p, u, max_s, min_d) in
            [("f32", 2f64.powi(-24), 5e18, 3.7e-23), ("f64", 2f64.powi(-53), 5e153, 1.5e-162)]
        {
            let e = bound_any_family(query, v, p).max_excess;
            let err = e * u * scale;
            let qps = rows
                .iter()
                .find(|r| {
                    r.workload == "random"
                        && r.query == query.name()
                        && r.implementation == v.name()
                        && r.precision == p
                        && r.threads == 1
                        && r.tolerance == "default"
                        && r.plain()
                })
                .map(|r| r.qps);
            let why = if scale > max_s {
                Some(format!(" (squared distances overflow {p} beyond S = {max_s:e})"))
            } else if tol < min_d {
                Some(format!(" (distances below {min_d:e} square to 0 in {p})"))
            } else {
                (err > tol).then(String::new)
            };
            options.push(Opt { v, p, e, err, qps, why });
        }
    }
    for o in &options {
        outln!(
            "{:8} {}: declared E <= {} -> distance error <= {:.3e} at S = {scale:e}; {} queries/s; {}",
            o.v.name(),
            o.p,
            o.e,
            o.err,
            o.qps.map(|q| format!("{q:.0}")).unwrap_or_else(|| "?".into()),
            o.why.as_ref().map_or("meets the tolerance".into(), |w| format!("does not meet it{w}"))
        );
    }
    let best = options
        .iter()
        .filter(|o| o.why.is_none() && o.qps.is_some())
        .max_by(|a, b| a.qps.unwrap_or(0.0).total_cmp(&b.qps.unwrap_or(0.0)));
    match best {
        Some(o) => {
            outln!(
                "\nadvice: {} {} ({:.0} queries/s on random pairs): its declared bound gives at most {:.3e} <= {tol:e}.",
                o.v.name(),
                o.p,
                o.qps.unwrap_or(0.0),
                o.err
            );
            Ok(ExitCode::SUCCESS)
        }
        None => {
            outln!("\nadvice: no variant meets a tolerance of {tol:e} at scale {scale:e} (the bound is E * u * S; f32 also cannot hold squared distances of coordinates beyond ~5e18 or distances below ~3.7e-23).");
            Ok(ExitCode::from(1))
        }
    }
}
