//! `tridist cases` (export the input families as case files) and `tridist judge` (judge another
//! implementation's answers to a case file against the exact oracle, with the metrics and the
//! per-family table of the reports).
//!
//! Case file: one pair per line, `label` and 18 coordinates (triangle A then B, shortest
//! round-trip decimals), optionally followed by `exact=NUM/DEN`, the oracle's exact squared
//! distance for the query named in the file's header. Blank lines and `#` lines are comments.
//!
//! A case with a non-finite coordinate (`nan`, `inf`) is bad input: its one right answer is
//! "no distance" (`nan` or `error`; `invalid` or `error` for `intersect`), and any number is
//! counted wrong. Such cases are judged apart from the families' table (the oracle measures
//! finite input only) and their wrong answers count as misclassified.
//!
//! Answer file: one line per case, in the same order (comments skipped alike), optionally
//! starting with the case's label (checked: a mismatch is an error, not a silent shift). Then,
//! for a distance query, the squared distance (`nan`, `inf` and `error` allowed), optionally
//! followed by the six coordinates of the closest points p (on A) and q (on B); for
//! `intersect`, one of `intersecting`, `disjoint`, `invalid` or `error`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;
use rug::Rational;
use serde_json::{json, Value};
use tridist::{Intersection, Interval, PathCounts, Query};
use tridist_scenes::bounds::VERDICT_ALLOW;
use tridist_scenes::eval::{case_line, parse_case_line_exact, summarise, truth, Output, Stats};
use tridist_scenes::families::generate;
use tridist_scenes::float::Float;
use tridist_scenes::{Case, Family};

use crate::{parse_query, Fail, Prec};

/// The queries a case file can be judged for.
const JUDGED: [Query; 4] = [Query::TriTri, Query::SegSeg, Query::PointTri, Query::Intersect];

fn parse_judged(s: &str) -> Result<Query, String> {
    let q = parse_query(s)?;
    if JUDGED.contains(&q) {
        Ok(q)
    } else {
        Err("judge and cases take tri_tri, seg_seg, point_tri or intersect".into())
    }
}

/// `all` or a family's name (anything else is a usage error).
fn parse_family(s: &str) -> Result<String, String> {
    if s == "all" || Family::parse(s).is_some() {
        Ok(s.to_string())
    } else {
        Err(format!("unknown family {s:?} (`tridist cases --list` names them)"))
    }
}

#[derive(Args, Debug)]
pub(crate) struct CasesArgs {
    /// A family name, or `all` (see --list).
    #[arg(long, default_value = "all", value_parser = parse_family)]
    family: String,
    /// Cases per family.
    #[arg(
        long,
        default_value_t = 100,
        value_parser = clap::value_parser!(u32).range(1..),
        allow_negative_numbers = true,
    )]
    count: u32,
    /// Generator seed (the reports use 1898041687, or $TRIDIST_SEED).
    #[arg(long, allow_negative_numbers = true)]
    seed: Option<u64>,
    /// Precision of the coordinates.
    #[arg(long, value_enum, default_value = "f64")]
    precision: Prec,
    /// Append `exact=NUM/DEN`, the exact squared distance of --query (0 for intersecting pairs).
    #[arg(long)]
    exact: bool,
    /// The query whose exact answer --exact appends (segment queries use the first edge of
    /// each triangle, point-triangle vertex 0 of B against A).
    #[arg(long, default_value = "tri_tri", value_parser = parse_judged)]
    query: Query,
    /// Name every family with what it stresses, then exit.
    #[arg(long)]
    list: bool,
}

#[derive(Args, Debug)]
pub(crate) struct JudgeArgs {
    /// The case file (from `tridist cases`, or any file in its format).
    #[arg(long, value_name = "FILE")]
    cases: PathBuf,
    /// The answers to judge, one line per case.
    #[arg(long, value_name = "FILE")]
    answers: PathBuf,
    /// Precision of the cases and answers.
    #[arg(long, value_enum)]
    precision: Prec,
    /// The question the answers answer.
    #[arg(long, default_value = "tri_tri", value_parser = parse_judged)]
    query: Query,
    /// Fail (exit 1) when the excess error E exceeds this anywhere.
    #[arg(long, value_name = "X", value_parser = crate::non_negative, allow_hyphen_values = true)]
    max_excess: Option<f64>,
    /// Fail (exit 1) when more cases than this are misclassified or non-finite (contact
    /// misses, false zeros beyond 8 u S, wrong verdicts, non-finite answers).
    #[arg(long, value_name = "N", default_value_t = 0, allow_negative_numbers = true)]
    max_misclassified: usize,
    /// Also write the table as JSON here.
    #[arg(long, value_name = "FILE")]
    json: Option<PathBuf>,
    /// The cases are mesh cases (`tridist mesh-cases`, corpus/mesh): answers are the squared
    /// distance, optionally followed by the triangle pair `I J`; wrong distances (beyond 64 u S),
    /// contact misses, false zeros, non-finite answers and wrong pairs count as misclassified.
    #[arg(long)]
    mesh: bool,
}

pub(crate) fn cmd_cases(a: &CasesArgs) -> Result<ExitCode, Fail> {
    if a.list {
        for f in Family::ALL {
            outln!("{:<14} {}", f.name(), f.about());
        }
        return Ok(ExitCode::SUCCESS);
    }
    let families: Vec<Family> = if a.family == "all" {
        Family::ALL.to_vec()
    } else {
        // parse_family let only `all` and the families' names through
        Family::parse(&a.family).into_iter().collect()
    };
    let seed = a.seed.unwrap_or_else(tridist_scenes::seed);
    let text = match a.precision {
        Prec::F32 => cases_text::<f32>(&families, seed, a),
        Prec::F64 => cases_text::<f64>(&families, seed, a),
    };
    out!("{text}");
    Ok(ExitCode::SUCCESS)
}

fn cases_text<T: Float>(families: &[Family], seed: u64, a: &CasesArgs) -> String {
    let mut s = format!(
        "# tridist cases: {} per family, seed {seed}, {}{}\n# label, then triangle A and triangle B (x y z per vertex){}\n",
        a.count,
        T::NAME,
        if a.exact { format!(", exact answers of {}", a.query.name()) } else { String::new() },
        if a.exact { ", then exact=NUM/DEN (squared distance)" } else { "" },
    );
    for &f in families {
        let cases = generate::<T>(f, seed, a.count as usize);
        let tr = a.exact.then(|| truth(a.query, &cases));
        for (i, c) in cases.iter().enumerate() {
            s.push_str(&case_line(c));
            if let Some(tr) = &tr {
                let _ = write!(s, " exact={}/{}", tr[i].d2.numer(), tr[i].d2.denom());
            }
            s.push('\n');
        }
    }
    s
}

/// Lines that are neither blank nor comments, with their 1-based numbers.
fn content_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'))
}

/// One parsed answer.
struct Answer<T> {
    d: T,
    points: Option<([T; 3], [T; 3])>,
    verdict: Intersection,
}

/// An answered squared distance: a number, or `nan`, `error` (none) or `inf`.
fn answer_number<T: Float>(s: &str) -> Result<T, String> {
    match s {
        "nan" | "NaN" | "error" => Ok(T::from_f64(f64::NAN)),
        "inf" | "+inf" => Ok(T::INFINITY),
        _ => s.parse::<T>().map_err(|_| format!("not a number: {s:?}")),
    }
}

fn is_answer_word(s: &str) -> bool {
    matches!(s, "nan" | "NaN" | "inf" | "+inf" | "error" | "intersecting" | "disjoint" | "invalid")
        || s.parse::<f64>().is_ok()
}

fn parse_answer<T: Float>(line: &str, case: &Case<T>, q: Query) -> Result<Answer<T>, String> {
    let mut toks: Vec<&str> = line.split_whitespace().collect();
    // a label is a leading field that is not an answer (a lone field is always the answer)
    if toks.len() > 1 && !is_answer_word(toks[0]) {
        if toks[0] != case.label {
            return Err(format!(
                "label {:?} but the case is {:?} (answers out of order or from another case file?)",
                toks[0], case.label
            ));
        }
        toks.remove(0);
    }
    let num = answer_number::<T>;
    if q.is_verdict() {
        let [w] = toks[..] else {
            return Err(format!("expected one verdict word, found {} fields", toks.len()));
        };
        let verdict = match w {
            "intersecting" => Intersection::Intersecting,
            "disjoint" => Intersection::Disjoint,
            "invalid" | "error" => Intersection::Invalid,
            _ => return Err(format!("expected intersecting, disjoint, invalid or error, found {w:?}")),
        };
        return Ok(Answer { d: T::ZERO, points: None, verdict });
    }
    match toks.len() {
        1 => Ok(Answer { d: num(toks[0]).map_err(|e| format!("{e} (nor nan, inf or error)"))?, points: None, verdict: Intersection::Invalid }),
        7 => {
            let v: Vec<T> = toks[1..].iter().map(|s| s.parse::<T>().map_err(|_| format!("not a number: {s:?}"))).collect::<Result<_, _>>()?;
            Ok(Answer {
                d: num(toks[0])?,
                points: Some(([v[0], v[1], v[2]], [v[3], v[4], v[5]])),
                verdict: Intersection::Invalid,
            })
        }
        n => Err(format!(
            "expected a squared distance, optionally followed by the 6 coordinates of the closest points; found {n} fields"
        )),
    }
}

fn read(path: &Path) -> Result<String, Fail> {
    std::fs::read_to_string(path).map_err(|e| Fail(format!("{}: {e}", path.display())))
}

pub(crate) fn cmd_judge(a: &JudgeArgs) -> Result<ExitCode, Fail> {
    let cases = read(&a.cases)?;
    let answers = read(&a.answers)?;
    if a.mesh {
        if a.query != Query::TriTri {
            return Err(Fail("--mesh judges mesh distances: no --query".into()));
        }
        return judge_mesh_files(&cases, &answers, a);
    }
    match a.precision {
        Prec::F32 => judge_as::<f32>(&cases, &answers, a),
        Prec::F64 => judge_as::<f64>(&cases, &answers, a),
    }
}

/// The cases with a non-finite coordinate, and the case-file lines of those answered with a
/// number.
#[derive(Default)]
struct BadInput {
    cases: usize,
    wrong: Vec<usize>,
}

/// The judgement of one family (or the whole file).
struct Group {
    family: String,
    stats: Stats,
    /// Largest closest-point error over the answers that gave points (None: none did).
    point_error: Option<f64>,
}

fn judge_as<T: Float>(cases_text: &str, answers_text: &str, a: &JudgeArgs) -> Result<ExitCode, Fail> {
    let (cf, af) = (a.cases.display(), a.answers.display());
    let mut all: Vec<Case<T>> = Vec::new();
    let mut all_exact: Vec<(usize, Option<Rational>)> = Vec::new();
    for (n, l) in content_lines(cases_text) {
        let (c, e) = parse_case_line_exact::<T>(l).map_err(|e| Fail(format!("{cf}: line {n}: {e}")))?;
        all.push(c);
        all_exact.push((n, e));
    }
    if all.is_empty() {
        return Err(Fail(format!("{cf}: no cases")));
    }
    let mut all_ans: Vec<Answer<T>> = Vec::with_capacity(all.len());
    for (n, l) in content_lines(answers_text) {
        let k = all_ans.len();
        let Some(c) = all.get(k) else {
            return Err(Fail(format!("{af}: line {n}: more answers than the {} cases", all.len())));
        };
        let x = parse_answer(l, c, a.query).map_err(|e| {
            Fail(format!("{af}: line {n}: {e} (answer to case {:?}, {cf} line {})", c.label, all_exact[k].0))
        })?;
        all_ans.push(x);
    }
    if all_ans.len() < all.len() {
        let k = all_ans.len();
        return Err(Fail(format!(
            "{af}: {} answers for {} cases (the first without an answer is {:?}, {cf} line {})",
            k,
            all.len(),
            all[k].label,
            all_exact[k].0
        )));
    }
    // Bad input (a non-finite coordinate) apart: right only when answered "no distance".
    let (mut cases, mut exact, mut ans) = (Vec::new(), Vec::new(), Vec::new());
    let mut bad = BadInput::default();
    for ((c, e), x) in all.into_iter().zip(all_exact).zip(all_ans) {
        if c.is_finite() {
            cases.push(c);
            exact.push(e);
            ans.push(x);
        } else {
            bad.cases += 1;
            let refused =
                if a.query.is_verdict() { x.verdict == Intersection::Invalid } else { x.d.is_nan() };
            if !refused {
                bad.wrong.push(e.0);
            }
        }
    }
    let tr = truth(a.query, &cases);
    for (t, (n, e)) in tr.iter().zip(&exact) {
        if let Some(e) = e {
            if *e != t.d2 {
                return Err(Fail(format!(
                    "{cf}: line {n}: its exact answer is not the oracle's ({}/{})",
                    t.d2.numer(),
                    t.d2.denom()
                )));
            }
        }
    }
    // Group by family (the label up to its first '/'), in order of first appearance.
    let mut fams: Vec<String> = Vec::new();
    let fam_of: Vec<usize> = cases
        .iter()
        .map(|c| {
            let f = c.label.split('/').next().unwrap_or("").to_string();
            fams.iter().position(|x| *x == f).unwrap_or_else(|| {
                fams.push(f);
                fams.len() - 1
            })
        })
        .collect();
    let mut groups: Vec<Group> = Vec::new();
    let mut judge_idx = |idx: &[usize], name: String| {
        let cs: Vec<Case<T>> = idx.iter().map(|&i| cases[i].clone()).collect();
        let ts: Vec<_> = idx.iter().map(|&i| tr[i].clone()).collect();
        let n = idx.len();
        let out = Output {
            d: idx.iter().map(|&i| ans[i].d).collect(),
            dist: Vec::new(),
            p: idx.iter().map(|&i| ans[i].points.map_or([T::ZERO; 3], |p| p.0)).collect(),
            q: idx.iter().map(|&i| ans[i].points.map_or([T::ZERO; 3], |p| p.1)).collect(),
            // no certificate: the interval that contains everything
            iv: vec![Interval { lo: T::ZERO, hi: T::INFINITY }; n],
            verdict: idx.iter().map(|&i| ans[i].verdict).collect(),
            certified: vec![false; n],
            counts: PathCounts::default(),
        };
        let (mut stats, js) = summarise(a.query, &cs, &ts, &out, VERDICT_ALLOW, None);
        let with_points: Vec<f64> = idx
            .iter()
            .zip(&js)
            .filter(|(&i, _)| ans[i].points.is_some())
            .map(|(_, j)| j.point_error)
            .collect();
        let point_error = (!with_points.is_empty()).then(|| with_points.iter().copied().fold(0.0, f64::max));
        stats.max_point_error = point_error.unwrap_or(0.0);
        groups.push(Group { family: name, stats, point_error });
    };
    for (k, f) in fams.iter().enumerate() {
        let idx: Vec<usize> = (0..cases.len()).filter(|&i| fam_of[i] == k).collect();
        judge_idx(&idx, f.clone());
    }
    if fams.len() > 1 {
        let idx: Vec<usize> = (0..cases.len()).collect();
        judge_idx(&idx, "all".into());
    }
    // (a wrong verdict beyond its allowance is counted once: as misjudged)
    let (max_excess, mut misclassified) = groups.last().map_or((0.0, 0), |total| {
        let st = &total.stats;
        let m = st.nonfinite
            + if a.query.is_verdict() { st.misjudged } else { st.contact_misses + st.false_zeros };
        (st.max_excess, m)
    });
    misclassified += bad.wrong.len();
    let excess_ok = a.max_excess.is_none_or(|m| max_excess <= m);
    let pass = excess_ok && misclassified <= a.max_misclassified;
    if !groups.is_empty() {
        out!("{}", table(a.query, T::NAME, &groups));
    }
    if bad.cases > 0 {
        let lines: Vec<String> = bad.wrong.iter().take(10).map(|n| n.to_string()).collect();
        outln!(
            "\nbad input (a non-finite coordinate): {} cases, {} answered with a number instead of {}{}",
            bad.cases,
            bad.wrong.len(),
            if a.query.is_verdict() { "invalid or error" } else { "nan or error" },
            if lines.is_empty() { String::new() } else { format!(" ({cf} lines {})", lines.join(", ")) }
        );
    }
    outln!(
        "\n{}: max E {} (limit {}), misclassified or non-finite {misclassified} (limit {})",
        if pass { "PASS" } else { "FAIL" },
        crate::common::fmt(max_excess),
        a.max_excess.map_or("none".into(), crate::common::fmt),
        a.max_misclassified
    );
    if let Some(path) = &a.json {
        let v = json!({
            "query": a.query.name(),
            "precision": T::NAME,
            "cases": cases.len() + bad.cases,
            "families": groups.iter().map(group_json).collect::<Vec<_>>(),
            "bad_input": { "cases": bad.cases, "answered_with_a_number": bad.wrong.len(), "lines": bad.wrong },
            "max_excess_limit": a.max_excess,
            "max_misclassified_limit": a.max_misclassified,
            "pass": pass,
        });
        let text = serde_json::to_string_pretty(&v).map_err(|e| Fail(e.to_string()))?;
        std::fs::write(path, text + "\n").map_err(|e| Fail(format!("{}: {e}", path.display())))?;
    }
    Ok(if pass { ExitCode::SUCCESS } else { ExitCode::from(1) })
}

/// A float for JSON: a number when finite, else the string "inf", "-inf" or "nan" (JSON has
/// no non-finite numbers).
fn num(x: f64) -> Value {
    if x.is_finite() {
        json!(x)
    } else if x.is_nan() {
        json!("nan")
    } else if x > 0.0 {
        json!("inf")
    } else {
        json!("-inf")
    }
}

fn group_json(g: &Group) -> Value {
    let s = &g.stats;
    json!({
        "family": g.family,
        "n": s.n,
        "max_excess": num(s.max_excess),
        "p99_excess": num(s.p99),
        "median_excess": num(s.median),
        "contact_misses": s.contact_misses,
        "false_zeros": s.false_zeros,
        "strict_false_zeros": s.strict_false_zeros,
        "nonfinite": s.nonfinite,
        "misjudged": s.misjudged,
        "max_point_error": g.point_error.map(num),
    })
}

fn table(q: Query, prec: &str, groups: &[Group]) -> String {
    let f = crate::common::fmt;
    let mut s = format!(
        "{} {prec}: E = |sqrt(answer) - exact distance| / (u S) beyond the correctly rounded answer (docs/ACCURACY.md)\n\n",
        q.name()
    );
    if q.is_verdict() {
        s.push_str("| family | cases | wrong \"disjoint\" | wrong \"intersecting\" (beyond 65 u S / any) | invalid |\n|---|---|---|---|---|\n");
        for g in groups {
            let st = &g.stats;
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} / {} | {} |",
                g.family, st.n, st.contact_misses, st.false_zeros, st.strict_false_zeros, st.nonfinite
            );
        }
        return s;
    }
    s.push_str("| family | cases | max E | p99 E | median E | contact misses | false zeros (beyond 8uS / strict) | non-finite | point error |\n|---|---|---|---|---|---|---|---|---|\n");
    for g in groups {
        let st = &g.stats;
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} / {} | {} | {} |",
            g.family,
            st.n,
            f(st.max_excess),
            f(st.p99),
            f(st.median),
            st.contact_misses,
            st.false_zeros,
            st.strict_false_zeros,
            st.nonfinite,
            g.point_error.map_or("-".into(), f)
        );
    }
    s
}

/// `judge --mesh`: a mesh case file and its answers.
fn judge_mesh_files(cases_text: &str, answers_text: &str, a: &JudgeArgs) -> Result<ExitCode, Fail> {
    let (cf, af) = (a.cases.display().to_string(), a.answers.display());
    let cases = crate::meshcases::parse_cases(cases_text, &cf)?;
    if let Some(c) = cases.iter().find(|c| c.exact.is_none()) {
        return Err(Fail(format!("{cf}: line {}: no exact=NUM/DEN answer", c.line)));
    }
    let dir = a.cases.parent().map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    let meshes = crate::meshcases::load_meshes(&cases, &dir)?;
    let mut ans: Vec<crate::meshcases::MeshAnswer> = Vec::new();
    for (n, l) in content_lines(answers_text) {
        let Some(c) = cases.get(ans.len()) else {
            return Err(Fail(format!("{af}: line {n}: more answers than the {} cases", cases.len())));
        };
        let mut t: Vec<&str> = l.split_whitespace().collect();
        if t.len() > 1 && !is_answer_word(t[0]) {
            if t[0] != c.label {
                return Err(Fail(format!("{af}: line {n}: label {:?} but the case is {:?}", t[0], c.label)));
            }
            t.remove(0);
        }
        let d2 = match t.first() {
            Some(x) => answer_number::<f64>(x).map_err(|e| Fail(format!("{af}: line {n}: {e}")))?,
            None => return Err(Fail(format!("{af}: line {n}: no answer"))),
        };
        let contacts = match t.last().and_then(|x| x.strip_prefix("contacts=")) {
            Some(list) => {
                let mut v =
                    crate::meshcases::parse_pairs(list).map_err(|e| Fail(format!("{af}: line {n}: {e}")))?;
                v.sort_unstable();
                t.pop();
                Some(v)
            }
            None => None,
        };
        let pair = match t[1..] {
            [] => None,
            [i, j] => {
                let p = |s: &str| s.parse::<usize>().map_err(|_| Fail(format!("{af}: line {n}: not a triangle index: {s:?}")));
                Some((p(i)?, p(j)?))
            }
            _ => {
                return Err(Fail(format!(
                    "{af}: line {n}: expected a squared distance, optionally followed by a triangle pair; found {} fields",
                    t.len()
                )))
            }
        };
        ans.push(crate::meshcases::MeshAnswer { d2, pair, contacts });
    }
    if ans.len() < cases.len() {
        return Err(Fail(format!("{af}: {} answers for {} cases", ans.len(), cases.len())));
    }
    let js = crate::meshcases::judge_mesh(&cases, &meshes, &ans, a.precision)?;
    let mut fams: Vec<String> = Vec::new();
    for c in &cases {
        let f = c.label.split('/').next().unwrap_or("").to_string();
        if !fams.contains(&f) {
            fams.push(f);
        }
    }
    let f = crate::common::fmt;
    out!(
        "mesh distance {}: E = |sqrt(answer) - exact distance| / (u S), wrong beyond {} u S\n\n\
         | family | cases | max E | wrong distances | contact misses | false zeros | non-finite | wrong pairs | contacts missed / extra |\n\
         |---|---|---|---|---|---|---|---|---|\n",
        match a.precision {
            Prec::F32 => "f32",
            Prec::F64 => "f64",
        },
        crate::meshcases::WRONG
    );
    let mut bad_lines: Vec<usize> = Vec::new();
    for fam in fams.iter().map(Some).chain([None]) {
        let idx: Vec<usize> = (0..cases.len())
            .filter(|&i| fam.is_none_or(|f| cases[i].label.split('/').next() == Some(f.as_str())))
            .collect();
        let n = |g: fn(&crate::meshcases::MeshJudged) -> bool| idx.iter().filter(|&&i| g(&js[i])).count();
        let max = idx.iter().map(|&i| js[i].excess).fold(0.0, f64::max);
        let contacts = crate::meshcases::contacts_total(idx.iter().map(|&i| &js[i]))
            .map_or_else(|| "-".to_string(), |(missed, extra, _)| format!("{missed} / {extra}"));
        outln!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {contacts} |",
            fam.map_or("all", |f| f.as_str()),
            idx.len(),
            f(max),
            n(|j| j.wrong),
            n(|j| j.contact_miss),
            n(|j| j.false_zero),
            n(|j| j.nonfinite),
            n(|j| j.wrong_pair)
        );
        if fam.is_none() {
            bad_lines = idx
                .iter()
                .filter(|&&i| {
                    let j = &js[i];
                    j.wrong
                        || j.contact_miss
                        || j.false_zero
                        || j.nonfinite
                        || j.wrong_pair
                        || j.contacts.is_some_and(|c| c.0 + c.1 > 0)
                })
                .map(|&i| cases[i].line)
                .collect();
        }
    }
    let max = js.iter().map(|j| j.excess).fold(0.0, f64::max);
    let pass = a.max_excess.is_none_or(|m| max <= m) && bad_lines.len() <= a.max_misclassified;
    let lines: Vec<String> = bad_lines.iter().take(10).map(|l| l.to_string()).collect();
    outln!(
        "\n{}: max E {} (limit {}), misclassified {} (limit {}){}",
        if pass { "PASS" } else { "FAIL" },
        f(max),
        a.max_excess.map_or("none".into(), f),
        bad_lines.len(),
        a.max_misclassified,
        if lines.is_empty() { String::new() } else { format!(" at {cf} lines {}", lines.join(", ")) }
    );
    if let Some(path) = &a.json {
        let v = json!({
            "mesh": true,
            "precision": match a.precision { Prec::F32 => "f32", Prec::F64 => "f64" },
            "cases": cases.len(),
            "max_excess": num(max),
            "misclassified_lines": bad_lines,
            "pass": pass,
        });
        let text = serde_json::to_string_pretty(&v).map_err(|e| Fail(e.to_string()))?;
        std::fs::write(path, text + "\n").map_err(|e| Fail(format!("{}: {e}", path.display())))?;
    }
    Ok(if pass { ExitCode::SUCCESS } else { ExitCode::from(1) })
}
