//! `tridist peers`: the conformance table (reports/PEERS.md). Every peer built into this binary,
//! in each precision and configuration it offers, and tridist's own variants, answer the
//! committed corpus (corpus/, format in corpus/README.md), judged against the corpus's exact
//! answers with the metrics of ACCURACY.md. Every failure counted is named by its file and line.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;
use rug::Rational;
use tridist::Query;
use tridist_oracle::metrics::magnitude;
use tridist_scenes::bounds::VERDICT_ALLOW;
use tridist_scenes::eval::{parse_case_line_exact, prec, run, summarise, Judged, Output, Truth, Variant};
use tridist_scenes::float::Float;
use tridist_scenes::peer::{self, Lib, Peer};
use tridist_scenes::Case;

use crate::common::{fmt, header};
use crate::{meshcases, Fail, Prec};

/// The excess error E a conforming answer stays within (ACCURACY.md's target).
const E_TARGET: f64 = 8.0;

/// The command that regenerates PEERS.md (its header names it).
pub(crate) const COMMAND: &str = "cargo run --release -p tridist-reports --features all-variants -- peers";

/// The levels of the conformance table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum Level {
    /// Triangle pairs only.
    Triangle,
    /// Meshes only.
    Mesh,
    /// Both.
    All,
}

#[derive(Args, Debug)]
pub(crate) struct PeersArgs {
    /// The corpus's triangle-level folder [default: corpus/triangle].
    #[arg(long, value_name = "DIR")]
    corpus: Option<PathBuf>,
    /// Which tables: triangle, mesh or all.
    #[arg(long, value_enum, default_value = "all")]
    level: Level,
    /// The corpus's mesh-level folder [default: corpus/mesh].
    #[arg(long, value_name = "DIR")]
    corpus_mesh: Option<PathBuf>,
    /// Write the table here [default: reports/PEERS.md].
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
}

/// One case file of the corpus, parsed: the cases, their exact answers and where each is.
struct Corpus<T> {
    /// The file as the table names it (relative to the repository when inside it).
    name: String,
    cases: Vec<Case<T>>,
    truth: Vec<Truth>,
    /// 1-based line of each case.
    lines: Vec<usize>,
    /// Family of each case (the label up to its first '/').
    family: Vec<String>,
}

impl<T> Corpus<T> {
    fn at(&self, i: usize) -> String {
        format!("{}:{}", self.name, self.lines[i])
    }
}

/// Reads a case file of the corpus; `exact` says whether every finite case must carry its
/// exact answer (`exact=NUM/DEN`), and finite and non-finite cases are both kept.
fn load<T: Float>(path: &Path, shown: String, exact: bool) -> Result<Corpus<T>, Fail> {
    let text = std::fs::read_to_string(path).map_err(|e| Fail(format!("{}: {e}", path.display())))?;
    let mut c = Corpus { name: shown, cases: vec![], truth: vec![], lines: vec![], family: vec![] };
    for (i, l) in text.lines().enumerate() {
        let l = l.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        let (case, e) =
            parse_case_line_exact::<T>(l).map_err(|e| Fail(format!("{}:{}: {e}", c.name, i + 1)))?;
        let coords = case.a.iter().chain(case.b.iter()).flatten().map(|x| x.to_f64());
        let d2 = match e {
            Some(e) => e,
            None if exact => return Err(Fail(format!("{}:{}: no exact=NUM/DEN answer", c.name, i + 1))),
            None => Rational::new(),
        };
        c.truth.push(Truth { d2, s: magnitude(coords, prec::<T>()) });
        c.family.push(case.label.split('/').next().unwrap_or("").to_string());
        c.cases.push(case);
        c.lines.push(i + 1);
    }
    if c.cases.is_empty() {
        return Err(Fail(format!("{}: no cases", c.name)));
    }
    Ok(c)
}

/// One row of the triangle-level table.
struct Row {
    library: String,
    version: String,
    configuration: String,
    precision: &'static str,
    /// None: not built (the reason).
    judged: Result<Judgement, String>,
}

/// What the judge found for one contender in one precision.
struct Judgement {
    families: usize,
    cases: usize,
    worst: (f64, String),
    p99: f64,
    /// Families over E = 8: (family, worst E, where).
    over: Vec<(String, f64, String)>,
    false_zeros: Vec<String>,
    contact_misses: Vec<String>,
    nonfinite: Vec<String>,
    /// Bad input answered with a number (where), out of how many; None: not judged.
    bad_input: Option<(Vec<String>, usize)>,
}

fn judgement<T: Float>(c: &Corpus<T>, out: &Output<T>, bad: Option<(&Corpus<T>, Vec<T>)>) -> Judgement {
    let (st, js): (_, Vec<Judged>) = summarise(Query::TriTri, &c.cases, &c.truth, out, VERDICT_ALLOW, None);
    let e = |j: &Judged| if j.excess.is_nan() { f64::INFINITY } else { j.excess };
    let mut fams: Vec<&str> = Vec::new();
    for f in &c.family {
        if !fams.contains(&f.as_str()) {
            fams.push(f);
        }
    }
    let over = fams
        .iter()
        .filter_map(|f| {
            let i = (0..js.len())
                .filter(|&i| c.family[i] == *f)
                .max_by(|&a, &b| e(&js[a]).total_cmp(&e(&js[b])))?;
            (e(&js[i]) > E_TARGET).then(|| (f.to_string(), e(&js[i]), c.at(i)))
        })
        .collect();
    let worst = (0..js.len()).max_by(|&a, &b| e(&js[a]).total_cmp(&e(&js[b]))).unwrap_or(0);
    let at = |flag: fn(&Judged) -> bool| -> Vec<String> {
        (0..js.len()).filter(|&i| flag(&js[i])).map(|i| c.at(i)).collect()
    };
    let bad_input = bad.map(|(b, d)| {
        let wrong = (0..b.cases.len()).filter(|&i| !d[i].is_nan()).map(|i| b.at(i)).collect();
        (wrong, b.cases.len())
    });
    Judgement {
        families: fams.len(),
        cases: js.len(),
        worst: (e(&js[worst]), c.at(worst)),
        p99: st.p99,
        over,
        false_zeros: at(|j| j.false_zero),
        contact_misses: at(|j| j.contact_miss),
        nonfinite: at(|j| j.nonfinite),
        bad_input,
    }
}

/// tridist's variants judged: the portable one, AVX2+FMA (what an AVX2-only CPU runs) and
/// the best this CPU runs, each once.
fn tridist_variants() -> Vec<Variant> {
    let mut v = vec![Variant::Soa, Variant::Avx2Fma];
    if let Ok(best) = Variant::auto() {
        v.push(best);
    }
    v.retain(|x| x.available());
    v.dedup();
    v
}

fn rows_for<T: Peer>(c: &Corpus<T>, bad: &Corpus<T>) -> Result<Vec<Row>, Fail> {
    let mut rows = Vec::new();
    for v in tridist_variants() {
        let out = run(Query::TriTri, v, &c.cases, None).map_err(|e| Fail(e.to_string()))?;
        let b = run(Query::TriTri, v, &bad.cases, None).map_err(|e| Fail(e.to_string()))?;
        rows.push(Row {
            library: "tridist".into(),
            version: env!("CARGO_PKG_VERSION").into(),
            configuration: format!(
                "`Engine::sqdist_triangle_triangle`, {} variant, default tolerance",
                v.name()
            ),
            precision: T::NAME,
            judged: Ok(judgement(c, &out, Some((bad, b.d)))),
        });
    }
    for lib in Lib::JUDGED.into_iter().filter(|l| l.offers::<T>()) {
        let judged = if lib.available() {
            let out = peer::answers(lib, &c.cases);
            // Coal and TrueForm are reached through models our adapter builds, and it refuses
            // non-finite coordinates before the library sees them: their bad input is not judged.
            let bad_answers =
                matches!(lib, Lib::Parry | Lib::Fcl).then(|| (bad, peer::answers(lib, &bad.cases).d));
            Ok(judgement(c, &out, bad_answers))
        } else {
            Err(lib.missing_reason().to_string())
        };
        rows.push(Row {
            library: lib.name().into(),
            version: lib.version().into(),
            configuration: lib.configuration::<T>().into(),
            precision: T::NAME,
            judged,
        });
    }
    Ok(rows)
}

/// A list of places, the first few.
fn places(v: &[String]) -> String {
    let mut s: Vec<String> = v.iter().take(3).cloned().collect();
    if v.len() > 3 {
        s.push(format!("and {} more", v.len() - 3));
    }
    s.join(", ")
}

fn count(v: &[String]) -> String {
    v.len().to_string()
}

fn table(rows: &[Row]) -> String {
    let mut s = String::from(
        "| library | version | configuration | precision | families | cases | worst E | p99 E | families over E = 8 | false zeros | contact misses | non-finite on finite input | bad input answered with a number |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let head = format!("| {} | {} | {} | {} ", r.library, r.version, r.configuration, r.precision);
        match &r.judged {
            Err(why) => {
                let _ = writeln!(s, "{head}| not built: {why} | | | | | | | | |");
            }
            Ok(j) => {
                let _ = writeln!(
                    s,
                    "{head}| {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                    j.families,
                    j.cases,
                    fmt(j.worst.0),
                    fmt(j.p99),
                    j.over.len(),
                    count(&j.false_zeros),
                    count(&j.contact_misses),
                    count(&j.nonfinite),
                    j.bad_input.as_ref().map_or("not judged".into(), |(w, n)| format!("{} of {n}", w.len())),
                );
            }
        }
    }
    s
}

fn failures(rows: &[Row]) -> String {
    let mut s = String::new();
    for r in rows {
        let Ok(j) = &r.judged else { continue };
        let mut items: Vec<String> = Vec::new();
        items.push(format!("worst E {} at {}", fmt(j.worst.0), j.worst.1));
        for (f, e, at) in &j.over {
            items.push(format!("{f}: E {} at {at}", fmt(*e)));
        }
        for (what, v) in [
            ("false zeros", &j.false_zeros),
            ("contact misses", &j.contact_misses),
            ("non-finite", &j.nonfinite),
        ] {
            if !v.is_empty() {
                items.push(format!("{what}: {}", places(v)));
            }
        }
        if let Some((w, _)) = &j.bad_input {
            if !w.is_empty() {
                items.push(format!("bad input answered with a number: {}", places(w)));
            }
        }
        let _ =
            writeln!(s, "- **{} ({}, {})**: {}.", r.library, r.configuration, r.precision, items.join("; "));
    }
    s
}

pub(crate) fn cmd_peers(a: &PeersArgs) -> Result<ExitCode, Fail> {
    let root = crate::root();
    let missing: Vec<&str> = Lib::JUDGED.iter().filter(|l| !l.available()).map(|l| l.name()).collect();
    let mut s =
        header("Conformance: every peer judged against the exact oracle", COMMAND, tridist_scenes::seed());
    let _ = write!(
        s,
        "Every library we can install answers the same committed corpus ([corpus/](../corpus/README.md)), \
         through its public API, in each precision and configuration it offers, and its answers are judged \
         against exact ones with the metrics of [docs/ACCURACY.md](../docs/ACCURACY.md): **E** = |answer - \
         exact distance| / (u S) beyond the correctly rounded answer; *false zeros* (0 reported for a pair \
         farther apart than 8 u S); *contact misses* (more than 8 u S reported for touching or intersecting \
         pairs); *non-finite* answers to finite input. Distances only: no peer's closest points are judged. \
         Every failure below names the case's file and line; `tridist judge --cases FILE` (with `--mesh` for \
         mesh cases) reproduces it from an answer file, which `tridist eval --peer NAME` (triangles) and \
         `tridist mesh-eval --peer NAME` (meshes) write for each peer built in.\n\n\
         The C++ peers are optional (how to get them: FCL `apt-get install libfcl-dev libeigen3-dev`; Coal and \
         TrueForm `bash scenes/peer/install.sh`; then rebuild); {}.\n",
        if missing.is_empty() {
            "every one was built into this run".to_string()
        } else {
            format!("not built into this run: {}", missing.join(", "))
        }
    );
    if a.level != Level::Mesh {
        s.push_str(&triangle_section(
            &root,
            &a.corpus.clone().unwrap_or_else(|| root.join("corpus/triangle")),
        )?);
    }
    if a.level != Level::Triangle {
        s.push_str(&mesh_section(&root, &a.corpus_mesh.clone().unwrap_or_else(|| root.join("corpus/mesh")))?);
    }
    let out = a.out.clone().unwrap_or_else(|| root.join("reports/PEERS.md"));
    std::fs::write(&out, s).map_err(|e| Fail(format!("{}: {e}", out.display())))?;
    eprintln!("wrote {}", out.display());
    Ok(ExitCode::SUCCESS)
}

/// The triangle-level section: every peer and tridist on the corpus's triangle pairs.
fn triangle_section(root: &Path, dir: &Path) -> Result<String, Fail> {
    let shown = |f: &str| {
        let p = dir.join(f);
        p.strip_prefix(root).map_or_else(|_| p.display().to_string(), |r| r.display().to_string())
    };
    let c32 = load::<f32>(&dir.join("tri_tri.f32.cases"), shown("tri_tri.f32.cases"), true)?;
    let c64 = load::<f64>(&dir.join("tri_tri.f64.cases"), shown("tri_tri.f64.cases"), true)?;
    let b32 = load::<f32>(&dir.join("bad_input.cases"), shown("bad_input.cases"), false)?;
    let b64 = load::<f64>(&dir.join("bad_input.cases"), shown("bad_input.cases"), false)?;
    if let Some(i) = b64.cases.iter().position(Case::is_finite) {
        return Err(Fail(format!("{}: a finite case in the bad-input file", b64.at(i))));
    }
    let non_finite = c32.cases.iter().position(|c| !c.is_finite()).map(|i| c32.at(i));
    if let Some(at) = non_finite.or_else(|| c64.cases.iter().position(|c| !c.is_finite()).map(|i| c64.at(i)))
    {
        return Err(Fail(format!("{at}: a non-finite coordinate (bad input belongs in bad_input.cases)")));
    }
    let mut rows = rows_for(&c32, &b32)?;
    rows.extend(rows_for(&c64, &b64)?);
    let mut s = format!(
        "\n## Triangle level\n\nThe input families of ACCURACY.md, {} pairs in f32 and {} in f64, each with its exact \
         squared distance as a fraction, and {} pairs with a NaN or infinite coordinate, whose right answer is \
         none (NaN, or an error): a number there is counted. A conforming answer stays within E = {E_TARGET}.\n\n",
        c32.cases.len(),
        c64.cases.len(),
        b64.cases.len(),
    );
    s.push_str(&table(&rows));
    s.push_str("\nWhere each row's worst case is, and every family over E = 8 or failure counted:\n\n");
    s.push_str(&failures(&rows));
    Ok(s)
}

/// The mesh-level section: every mesh contender on the corpus's mesh cases.
fn mesh_section(root: &Path, dir: &Path) -> Result<String, Fail> {
    let file = dir.join(meshcases::CASE_FILE);
    let shown =
        file.strip_prefix(root).map_or_else(|_| file.display().to_string(), |r| r.display().to_string());
    let text = std::fs::read_to_string(&file).map_err(|e| Fail(format!("{}: {e}", file.display())))?;
    let cases = meshcases::parse_cases(&text, &shown)?;
    let meshes = meshcases::load_meshes(&cases, dir)?;
    let family = |c: &meshcases::MeshCase| c.label.split('/').next().unwrap_or("").to_string();
    let mut fams: Vec<String> = Vec::new();
    for c in &cases {
        if !fams.contains(&family(c)) {
            fams.push(family(c));
        }
    }
    let mut s = format!(
        "\n## Mesh level\n\nThe same libraries' mesh distance on [{shown}](../{shown}): {} placed pairs of the \
         meshes beside it ({}), in {} families ({}). Each case's exact answer is the smallest exact squared \
         distance over all triangle pairs of the two meshes placed exactly (`R v + t` in rationals), found by \
         an exact computation over every pair that a sweep of padded boxes cannot rule out (not by any \
         library's search; corpus/README.md). Each library places the meshes itself, in its own precision: \
         E is measured in that precision's u, with S the largest coordinate of the placed meshes. A \
         **wrong distance** is one beyond {} u S (MESH.md's threshold) or none; a **wrong pair** a reported \
         triangle pair whose exact distance exceeds the minimum by more than that (only tridist reports its \
         pair here). **Contacts**: at the close scenes, the triangle pairs within a margin of 1 % of the \
         size, against the exact set: missed (exactly within the margin less that bound, not reported) and \
         extra (reported, exactly beyond the margin plus that bound); only tridist has such a query here.\n\n\
         | library | version | configuration | precision | families | cases | worst E | wrong distances | false zeros | contact misses | non-finite | wrong pairs | contacts missed / extra |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
        cases.len(),
        {
            let mut names: Vec<&str> = meshes.keys().map(String::as_str).collect();
            names.sort_unstable();
            names.join(", ")
        },
        fams.len(),
        fams.join(", "),
        meshcases::WRONG,
    );
    let mut bullets = String::new();
    for (who, lib, version, config) in meshcases::contenders() {
        let prec = who.precision();
        let pname = match prec {
            Prec::F32 => "f32",
            Prec::F64 => "f64",
        };
        let head = format!("| {lib} | {version} | {config} | {pname} ");
        let answers = match meshcases::answers(who, &cases, &meshes) {
            Ok(a) => a,
            Err(Fail(why)) => {
                let _ = writeln!(s, "{head}| not built: {why} | | | | | | | | |");
                continue;
            }
        };
        let js = meshcases::judge_mesh(&cases, &meshes, &answers, prec)?;
        let at = |i: usize| format!("{shown}:{}", cases[i].line);
        let list = |f: fn(&meshcases::MeshJudged) -> bool| -> Vec<String> {
            (0..js.len()).filter(|&i| f(&js[i])).map(at).collect()
        };
        let worst = (0..js.len()).max_by(|&a, &b| js[a].excess.total_cmp(&js[b].excess)).unwrap_or(0);
        let (wrong, fz, cm, nf, wp) = (
            list(|j| j.wrong),
            list(|j| j.false_zero),
            list(|j| j.contact_miss),
            list(|j| j.nonfinite),
            list(|j| j.wrong_pair),
        );
        let reports_pairs = answers.iter().any(|a| a.pair.is_some());
        let contacts = meshcases::contacts_total(js.iter()).map_or_else(
            || "no contact query".to_string(),
            |(missed, extra, n)| format!("{missed} / {extra} ({n} cases)"),
        );
        let contact_faults = list(|j| j.contacts.is_some_and(|c| c.0 + c.1 > 0));
        let _ = writeln!(
            s,
            "{head}| {} | {} | {} | {} | {} | {} | {} | {} | {contacts} |",
            fams.len(),
            cases.len(),
            fmt(js[worst].excess),
            wrong.len(),
            fz.len(),
            cm.len(),
            nf.len(),
            if reports_pairs { wp.len().to_string() } else { "no pair reported".into() },
        );
        let mut items = vec![format!("worst E {} at {}", fmt(js[worst].excess), at(worst))];
        for (what, v) in [
            ("wrong distances", &wrong),
            ("false zeros", &fz),
            ("contact misses", &cm),
            ("non-finite", &nf),
            ("wrong pairs", &wp),
            ("contacts missed or extra", &contact_faults),
        ] {
            if !v.is_empty() {
                items.push(format!("{what}: {}", places(v)));
            }
        }
        let _ = writeln!(bullets, "- **{lib} ({config}, {pname})**: {}.", items.join("; "));
    }
    s.push_str("\nWhere each row's worst case is, and every failure counted:\n\n");
    s.push_str(&bullets);
    Ok(s)
}
