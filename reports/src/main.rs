//! The `tridist` command: regenerate the reports, evaluate pairs from stdin, time a file of
//! pairs, and advise a variant for a scene.

mod common;
mod report;
mod svg;

use std::io::Read;
use std::process::ExitCode;
use std::time::Duration;

use tridist::Real;
use tridist_scenes::bounds::bound;
use tridist_scenes::eval::{parse_case_line, run, summarise, truth, Output, Query, Variant};
use tridist_scenes::{Case, Family};

const USAGE: &str = "\
tridist: fast triangle distance kernels, measured

USAGE:
  tridist report [--quick] [--out DIR]
      Accuracy sweep + throughput + plots into reports/ (ACCURACY.md, THROUGHPUT.md,
      TRADEOFF.md, *.svg, throughput.csv) and the README results section.
  tridist eval [--kernel pqp|brute|penalty|oracle] [--variant scalar|soa|sse41|avx|avx2fma|auto]
               [--precision f32|f64] [--exact] [--check] [--list]
      Reads pairs from stdin (label + 18 coordinates per line; blank and # lines ignored),
      prints `label squared_distance` per pair.
  tridist bench --input FILE [--kernel pqp|brute] [--variant ..] [--precision ..] [--reps N]
      Times the batch query over the pairs in FILE: queries per second.
  tridist advise --scale S --tolerance T [--query tri_tri|tri_tri_brute|seg_seg|point_tri]
      Picks the fastest variant whose declared error bound meets an absolute distance
      tolerance T at coordinate magnitude S.
";

/// Parsed `--flag value` options.
struct Opts {
    kv: Vec<(String, Option<String>)>,
}

impl Opts {
    fn parse(args: &[String], flags: &[&str], valued: &[&str]) -> Result<Opts, String> {
        let mut kv = Vec::new();
        let mut i = 0;
        while i < args.len() {
            let a = &args[i];
            if flags.contains(&a.as_str()) {
                kv.push((a.clone(), None));
            } else if valued.contains(&a.as_str()) {
                let v = args.get(i + 1).ok_or_else(|| format!("{a} needs a value"))?;
                kv.push((a.clone(), Some(v.clone())));
                i += 1;
            } else {
                return Err(format!("unknown argument {a:?}"));
            }
            i += 1;
        }
        Ok(Opts { kv })
    }
    fn flag(&self, k: &str) -> bool {
        self.kv.iter().any(|(a, _)| a == k)
    }
    fn get(&self, k: &str) -> Option<&str> {
        self.kv.iter().rev().find(|(a, _)| a == k).and_then(|(_, v)| v.as_deref())
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let res = match args.first().map(String::as_str) {
        Some("report") => cmd_report(&args[1..]),
        Some("eval") => cmd_eval(&args[1..]),
        Some("bench") => cmd_bench(&args[1..]),
        Some("advise") => cmd_advise(&args[1..]),
        Some("help" | "--help" | "-h") => {
            print!("{USAGE}");
            Ok(ExitCode::SUCCESS)
        }
        Some(other) => Err(format!("unknown command {other:?}")),
        None => Err("no command given".into()),
    };
    match res {
        Ok(c) => c,
        Err(e) => {
            eprintln!("tridist: {e}\n\n{USAGE}");
            ExitCode::from(2)
        }
    }
}

fn cmd_report(args: &[String]) -> Result<ExitCode, String> {
    let o = Opts::parse(args, &["--quick"], &["--out"])?;
    let quick = o.flag("--quick");
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let out_dir = o.get("--out").map(std::path::PathBuf::from).unwrap_or_else(|| root.join("reports"));
    let s = report::Settings {
        cases: if quick { 150 } else { 1500 },
        pairs: if quick { 2000 } else { 10_000 },
        budget: Duration::from_millis(if quick { 40 } else { 300 }),
        command: format!(
            "cargo run --release -p tridist-reports -- report{}",
            if quick { " --quick" } else { "" }
        ),
        readme: if o.get("--out").is_none() { Some(root.join("README.md")) } else { None },
        out_dir,
    };
    report::run_report(&s)?;
    eprintln!("wrote {}", s.out_dir.display());
    Ok(ExitCode::SUCCESS)
}

#[derive(Clone, Copy, PartialEq)]
enum Kernel {
    Pqp,
    Brute,
    Oracle,
}

fn kernel_of(o: &Opts) -> Result<Kernel, String> {
    match o.get("--kernel").unwrap_or("pqp") {
        "pqp" => Ok(Kernel::Pqp),
        "brute" => Ok(Kernel::Brute),
        "oracle" => Ok(Kernel::Oracle),
        "penalty" => Err("kernel penalty is not implemented yet (see the penalty-method issue)".into()),
        k => Err(format!("unknown kernel {k:?} (pqp, brute, penalty, oracle)")),
    }
}

fn variant_of(o: &Opts) -> Result<Variant, String> {
    let v = o.get("--variant").unwrap_or("auto");
    let var = Variant::parse(v)
        .ok_or_else(|| format!("unknown variant {v:?} (scalar, soa, sse41, avx, avx2fma, auto)"))?;
    if !var.available() {
        return Err(format!("variant {v} is not available on this CPU"));
    }
    Ok(var)
}

/// Reads case lines; returns parsed cases (with their line numbers) and the parse errors.
fn read_cases<T: Real>(text: &str) -> (Vec<(usize, Case<T>)>, Vec<String>) {
    let mut cases = Vec::new();
    let mut errors = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let l = line.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        match parse_case_line::<T>(l) {
            Ok(c) => cases.push((i + 1, c)),
            Err(e) => errors.push(format!("line {}: {e}", i + 1)),
        }
    }
    (cases, errors)
}

fn cmd_eval(args: &[String]) -> Result<ExitCode, String> {
    let o = Opts::parse(args, &["--exact", "--check", "--list"], &["--kernel", "--variant", "--precision"])?;
    if o.flag("--list") {
        for k in ["pqp", "brute"] {
            for v in Variant::ALL.iter().filter(|v| v.available()) {
                for p in ["f32", "f64"] {
                    println!("{k} {} {p}", v.name());
                }
            }
        }
        println!("oracle exact f32\noracle exact f64");
        return Ok(ExitCode::SUCCESS);
    }
    let kernel = kernel_of(&o)?;
    let variant = variant_of(&o)?;
    if o.flag("--exact") && kernel != Kernel::Oracle {
        return Err("--exact needs --kernel oracle".into());
    }
    let mut text = String::new();
    std::io::stdin().read_to_string(&mut text).map_err(|e| format!("reading stdin: {e}"))?;
    match o.get("--precision").unwrap_or("f64") {
        "f32" => eval_as::<f32>(&text, kernel, variant, o.flag("--exact"), o.flag("--check")),
        "f64" => eval_as::<f64>(&text, kernel, variant, o.flag("--exact"), o.flag("--check")),
        p => Err(format!("unknown precision {p:?} (f32, f64)")),
    }
}

fn eval_as<T: Real>(
    text: &str,
    kernel: Kernel,
    variant: Variant,
    exact: bool,
    check: bool,
) -> Result<ExitCode, String> {
    let (cases, errors) = read_cases::<T>(text);
    for e in &errors {
        eprintln!("tridist eval: {e}");
    }
    let cs: Vec<Case<T>> = cases.iter().map(|(_, c)| c.clone()).collect();
    let q = if kernel == Kernel::Brute { Query::TriTriBrute } else { Query::TriTri };
    let out =
        if kernel == Kernel::Oracle { None } else { Some(run(q, variant, &cs).map_err(|e| e.to_string())?) };
    for (i, c) in cs.iter().enumerate() {
        let finite = c.a.iter().chain(c.b.iter()).flatten().all(|x| x.is_finite());
        let mut line = c.label.clone();
        match &out {
            Some(o) => line.push_str(&format!(" {:?}", o.d[i])),
            None => {
                let a = c.a.map(|p| p.map(|x| x.to_f64()));
                let b = c.b.map(|p| p.map(|x| x.to_f64()));
                match tridist_oracle::sqdist_triangle_triangle(&a, &b) {
                    Ok(d) if exact => line.push_str(&format!(" {}/{}", d.numer(), d.denom())),
                    Ok(d) => {
                        let r = if T::NAME == "f32" {
                            tridist_oracle::round::to_f32(&d) as f64
                        } else {
                            tridist_oracle::round::to_f64(&d)
                        };
                        line.push_str(&format!(
                            " {}",
                            if T::NAME == "f32" { format!("{:?}", r as f32) } else { format!("{r:?}") }
                        ));
                    }
                    Err(e) => line.push_str(&format!(" error: {e}")),
                }
            }
        }
        if check && finite {
            if let Some(o) = &out {
                let one = vec![c.clone()];
                let t = truth(q, &one);
                let single = Output { d: vec![o.d[i]], p: vec![o.p[i]], q: vec![o.q[i]] };
                let (st, _) = summarise(q, &one, &t, &single);
                line.push_str(&format!(" E={}", st.max_excess));
            } else {
                line.push_str(" E=0");
            }
        }
        println!("{line}");
    }
    Ok(if errors.is_empty() { ExitCode::SUCCESS } else { ExitCode::from(1) })
}

fn cmd_bench(args: &[String]) -> Result<ExitCode, String> {
    let o = Opts::parse(args, &[], &["--input", "--kernel", "--variant", "--precision", "--reps"])?;
    let path = o.get("--input").ok_or("--input FILE is required")?;
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let kernel = kernel_of(&o)?;
    if kernel == Kernel::Oracle {
        return Err("bench times the kernels; use --kernel pqp or brute".into());
    }
    let variant = variant_of(&o)?;
    let reps: usize = match o.get("--reps") {
        None => 11,
        Some(s) => s
            .parse()
            .ok()
            .filter(|&n| n > 0)
            .ok_or_else(|| format!("--reps needs a positive integer, got {s:?}"))?,
    };
    match o.get("--precision").unwrap_or("f64") {
        "f32" => bench_as::<f32>(&text, kernel, variant, reps),
        "f64" => bench_as::<f64>(&text, kernel, variant, reps),
        p => Err(format!("unknown precision {p:?} (f32, f64)")),
    }
}

fn bench_as<T: Real>(text: &str, kernel: Kernel, variant: Variant, reps: usize) -> Result<ExitCode, String> {
    let (cases, errors) = read_cases::<T>(text);
    if !errors.is_empty() {
        return Err(format!("{} malformed line(s), first: {}", errors.len(), errors[0]));
    }
    if cases.is_empty() {
        return Err("no pairs in the input".into());
    }
    let a: Vec<_> = cases.iter().map(|(_, c)| c.a).collect();
    let b: Vec<_> = cases.iter().map(|(_, c)| c.b).collect();
    let (ba, bb) = (tridist::TriangleBatch::from_slice(&a), tridist::TriangleBatch::from_slice(&b));
    let e = tridist::Engine::new(variant.isa()).map_err(|e| e.to_string())?;
    let mut out = vec![T::ZERO; a.len()];
    let aos = variant == Variant::Scalar;
    let mut pass = || -> Result<(), tridist::Error> {
        match (kernel == Kernel::Brute, aos) {
            (false, true) => e.sqdist_triangle_triangle(&a, &b, &mut out),
            (false, false) => e.sqdist_triangle_triangle(&ba, &bb, &mut out),
            (true, true) => e.sqdist_triangle_triangle_brute(&a, &b, &mut out),
            (true, false) => e.sqdist_triangle_triangle_brute(&ba, &bb, &mut out),
        }
    };
    pass().map_err(|e| e.to_string())?;
    let mut times = Vec::with_capacity(reps);
    for _ in 0..reps {
        let t = std::time::Instant::now();
        pass().map_err(|e| e.to_string())?;
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(|x, y| x.total_cmp(y));
    let med = times[times.len() / 2];
    println!(
        "{} pairs, {} {} {}: {:.0} queries/s (median of {reps} passes after one warm-up)",
        a.len(),
        if kernel == Kernel::Brute { "brute" } else { "pqp" },
        variant.name(),
        T::NAME,
        a.len() as f64 / med
    );
    Ok(ExitCode::SUCCESS)
}

fn cmd_advise(args: &[String]) -> Result<ExitCode, String> {
    let o = Opts::parse(args, &[], &["--scale", "--tolerance", "--query", "--csv"])?;
    let num = |k: &str| -> Result<f64, String> {
        let s = o.get(k).ok_or_else(|| format!("{k} is required"))?;
        s.parse::<f64>()
            .ok()
            .filter(|x| x.is_finite() && *x > 0.0)
            .ok_or_else(|| format!("{k} needs a positive finite number, got {s:?}"))
    };
    let scale = num("--scale")?;
    let tol = num("--tolerance")?;
    let qn = o.get("--query").unwrap_or("tri_tri");
    let query =
        Query::parse(qn).filter(|q| *q != Query::Intersect).ok_or_else(|| format!("unknown query {qn:?}"))?;
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let csv_path =
        o.get("--csv").map(std::path::PathBuf::from).unwrap_or_else(|| root.join("reports/throughput.csv"));
    let csv = std::fs::read_to_string(&csv_path)
        .map_err(|e| format!("{}: {e} (run `tridist report` first)", csv_path.display()))?;
    let tq = match query {
        Query::SegSeg => "seg_seg",
        Query::PointTri => "tri_point",
        Query::TriTriBrute => "tri_tri_brute",
        _ => "tri_tri",
    };
    let mut options = Vec::new();
    for v in Variant::ALL.iter().filter(|v| v.available()) {
        for (p, u, max_s, min_d) in
            [("f32", 2f64.powi(-24), 5e18, 3.7e-23), ("f64", 2f64.powi(-53), 5e153, 1.5e-162)]
        {
            let e = Family::ALL.iter().map(|&f| bound(query, *v, p, f).max_excess).fold(0.0, f64::max);
            let err = e * u * scale;
            let qps = csv
                .lines()
                .filter_map(|l| {
                    let c: Vec<&str> = l.split(',').collect();
                    (c.len() == 5
                        && c[0] == "random unit cube"
                        && c[1] == tq
                        && c[2] == v.name()
                        && c[3] == p)
                        .then(|| c[4].parse::<f64>().ok())
                        .flatten()
                })
                .next();
            let fits = err <= tol && scale <= max_s && tol >= min_d;
            options.push((v.name(), p, e, err, qps, fits));
        }
    }
    let best = options
        .iter()
        .filter(|o| o.5 && o.4.is_some())
        .max_by(|a, b| a.4.unwrap_or(0.0).total_cmp(&b.4.unwrap_or(0.0)));
    for (v, p, e, err, qps, fits) in &options {
        println!(
            "{v:8} {p}: declared E <= {e} -> distance error <= {err:.3e} at S = {scale:e}; {} queries/s; {}",
            qps.map(|q| format!("{q:.0}")).unwrap_or_else(|| "?".into()),
            if *fits { "meets the tolerance" } else { "does not meet it" }
        );
    }
    match best {
        Some((v, p, _, err, qps, _)) => {
            println!("\nadvice: {v} {p} ({:.0} queries/s on random pairs): its declared bound gives at most {err:.3e} <= {tol:e}.", qps.unwrap_or(0.0));
            Ok(ExitCode::SUCCESS)
        }
        None => {
            println!("\nadvice: no variant meets a tolerance of {tol:e} at scale {scale:e} (the bound is E * u * S; f32 also cannot hold squared distances of coordinates beyond ~5e18 or distances below ~3.7e-23).");
            Ok(ExitCode::from(1))
        }
    }
}
