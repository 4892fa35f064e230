//! `tridist cases` and `tridist judge` end to end, as an outside project runs them: export a
//! family, answer it with an implementation (ours through `eval`, parry through `eval --peer`,
//! a naive program), judge the answers from files, and get exactly the figures the reports
//! compute in-process for the same cases. Malformed and misaligned answer files are errors with
//! line numbers; limits give exit status 1.

mod common;
use common::tridist;

use std::path::{Path, PathBuf};

use serde_json::Value;
use tridist::Query;
use tridist_scenes::eval::{sweep_family, Stats, Variant};
use tridist_scenes::peer::{self, Lib};
use tridist_scenes::Family;

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tridist-judge-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn write(p: &Path, text: &str) -> String {
    std::fs::write(p, text).unwrap();
    p.display().to_string()
}

fn cases(family: &str, n: u32, seed: u64, prec: &str, extra: &[&str]) -> String {
    let (n, seed) = (n.to_string(), seed.to_string());
    let mut args = vec!["cases", "--family", family, "--count", &n, "--seed", &seed, "--precision", prec];
    args.extend(extra);
    let (code, out, err) = tridist(&args, "");
    assert_eq!(code, 0, "{err}");
    out
}

/// Runs judge; returns (exit status, stdout, stderr, the JSON when written).
fn judge(
    cases: &str,
    answers: &str,
    prec: &str,
    extra: &[&str],
    d: &Path,
) -> (i32, String, String, Option<Value>) {
    let c = write(&d.join("cases.txt"), cases);
    let a = write(&d.join("answers.txt"), answers);
    let j = d.join("judge.json");
    let _ = std::fs::remove_file(&j);
    let js = j.display().to_string();
    let mut args = vec!["judge", "--cases", &c, "--answers", &a, "--precision", prec, "--json", &js];
    args.extend(extra);
    let (code, out, err) = tridist(&args, "");
    let v =
        std::fs::read_to_string(&j).ok().map(|t| serde_json::from_str(&t).expect("judge writes valid JSON"));
    (code, out, err, v)
}

fn num(v: &Value) -> f64 {
    match v {
        Value::Number(n) => n.as_f64().unwrap(),
        Value::String(s) if s == "inf" => f64::INFINITY,
        Value::String(s) if s == "nan" => f64::NAN,
        _ => panic!("not a number: {v}"),
    }
}

/// The judge's figures for one family equal the in-process ones, bit for bit.
fn assert_same(v: &Value, fam: &str, st: &Stats, points: bool) {
    let g = v["families"].as_array().unwrap().iter().find(|g| g["family"] == fam).expect("family row");
    assert_eq!(g["n"], st.n);
    assert_eq!(num(&g["max_excess"]).to_bits(), st.max_excess.to_bits(), "max E {g}");
    assert_eq!(num(&g["p99_excess"]).to_bits(), st.p99.to_bits(), "p99 {g}");
    assert_eq!(num(&g["median_excess"]).to_bits(), st.median.to_bits(), "median {g}");
    assert_eq!(g["contact_misses"], st.contact_misses);
    assert_eq!(g["false_zeros"], st.false_zeros);
    assert_eq!(g["strict_false_zeros"], st.strict_false_zeros);
    assert_eq!(g["nonfinite"], st.nonfinite);
    if points {
        assert_eq!(num(&g["max_point_error"]).to_bits(), st.max_point_error.to_bits(), "points {g}");
    } else {
        assert!(g["max_point_error"].is_null());
    }
}

#[test]
fn cases_are_reproducible_listed_and_carry_the_oracles_exact_answer() {
    let a = cases("all", 3, 11, "f32", &[]);
    assert_eq!(a, cases("all", 3, 11, "f32", &[]), "same seed, same bytes");
    assert_ne!(a, cases("all", 3, 12, "f32", &[]));
    let (code, list, _) = tridist(&["cases", "--list"], "");
    assert_eq!(code, 0);
    for f in Family::ALL {
        assert!(list.lines().any(|l| l.starts_with(f.name())), "{} not listed", f.name());
        assert_eq!(a.lines().filter(|l| l.starts_with(&format!("{}/", f.name()))).count(), 3);
    }
    // --exact appends the oracle's fraction; judge re-derives it and refuses a tampered one
    let ex = cases("touching", 4, 5, "f64", &["--exact"]);
    assert!(ex.lines().filter(|l| !l.starts_with('#')).all(|l| l.contains(" exact=")), "{ex}");
    let d = dir("exact");
    let answers: String = ex.lines().filter(|l| !l.starts_with('#')).map(|_| "0\n").collect();
    let (code, _, err, _) = judge(&ex, &answers, "f64", &[], &d);
    assert_eq!(code, 0, "touching pairs are at distance 0: {err}");
    let tampered = ex.replacen(" exact=0/1", " exact=1/3", 1);
    assert_ne!(tampered, ex);
    let (code, _, err, _) = judge(&tampered, &answers, "f64", &[], &d);
    assert_eq!(code, 3);
    assert!(err.contains("line 3") && err.contains("not the oracle's"), "{err}");
    // eval reads the same file (the fractions ignored), and its answers pass the judge
    let (code, ours, err) = tridist(&["eval", "--precision", "f64"], &ex);
    assert_eq!(code, 0, "{err}");
    assert_eq!(ours.lines().count(), answers.lines().count(), "{ours}");
    let (code, out, err, _) = judge(&ex, &ours, "f64", &["--max-excess", "8"], &d);
    assert_eq!(code, 0, "{out}{err}");
    // an unknown family is a usage error (exit 2, before any work), as an unknown kernel is
    let (code, out, err) = tridist(&["cases", "--family", "nope"], "");
    assert_eq!(code, 2, "{err}");
    assert!(out.is_empty() && err.contains("unknown family \"nope\"") && err.contains("--help"), "{err}");
}

/// Our kernel through files (`cases` -> `eval --points` -> `judge`) gives exactly the figures
/// the report computes in-process for the same cases; so does parry through `eval --peer`.
#[test]
fn judging_through_files_gives_the_reports_figures() {
    let (seed, n) = (1898041687u64, 120u32);
    let v = Variant::ALL.into_iter().rev().find(|v| v.available()).unwrap();
    let d = dir("roundtrip");
    for fam in [Family::NearParallel, Family::Degenerate, Family::Touching] {
        let text = cases(fam.name(), n, seed, "f32", &[]);
        let (code, answers, err) = tridist(
            &["eval", "--kernel", "tri_tri", "--variant", v.name(), "--precision", "f32", "--points"],
            &text,
        );
        assert_eq!(code, 0, "{err}");
        let (code, out, err, json) = judge(&text, &answers, "f32", &["--max-excess", "8"], &d);
        assert_eq!(code, 0, "{out}{err}");
        let rows = sweep_family::<f32>(Query::TriTri, fam, seed, n as usize, |_, _| {});
        let row = rows.iter().find(|r| r.variant == v).unwrap();
        assert_same(json.as_ref().unwrap(), fam.name(), &row.stats, true);
        assert!(out.contains(&format!("| {} | {n} |", fam.name())), "{out}");

        let (code, answers, err) = tridist(
            &["eval", "--peer", "parry3d", "--precision", "f64"],
            &cases(fam.name(), n, seed, "f64", &[]),
        );
        assert_eq!(code, 0, "{err}");
        let (_, _, err, json) = judge(
            &cases(fam.name(), n, seed, "f64", &[]),
            &answers,
            "f64",
            &["--max-misclassified", "1000000"],
            &d,
        );
        let st = peer::judge::<f64>(Lib::Parry, fam, seed, n as usize);
        assert_same(json.as_ref().unwrap_or_else(|| panic!("{err}")), fam.name(), &st, false);
    }
}

/// A naive implementation (closest vertex pair) is caught: exit 1, the excess in the table.
#[test]
fn a_wrong_implementation_fails_the_judgement() {
    let text = cases("random", 50, 3, "f64", &[]);
    let answers: String = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().skip(1).map(|x| x.parse().unwrap()).collect();
            let mut best = f64::INFINITY;
            for i in 0..3 {
                for j in 3..6 {
                    best = best.min((0..3).map(|k| (v[3 * i + k] - v[3 * j + k]).powi(2)).sum());
                }
            }
            format!("{best:?}\n")
        })
        .collect();
    let d = dir("naive");
    let (code, out, _, json) = judge(&text, &answers, "f64", &["--max-excess", "8"], &d);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("FAIL"), "{out}");
    let json = json.unwrap();
    assert!(num(&json["families"][0]["max_excess"]) > 1e10);
    assert_eq!(json["pass"], false);
    // without the excess limit it still fails: it misses every intersecting pair
    let intersecting = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .filter(|l| {
            let (_, o, _) = tridist(&["eval", "--kernel", "oracle"], l);
            o.trim_end().ends_with(" 0.0")
        })
        .count();
    assert!(intersecting > 0);
    let (code, out, _, json) = judge(&text, &answers, "f64", &[], &d);
    assert_eq!(code, 1, "{out}");
    assert_eq!(json.unwrap()["families"][0]["contact_misses"], intersecting);
    let allowed = intersecting.to_string();
    let (code, out, _, _) = judge(&text, &answers, "f64", &["--max-misclassified", &allowed], &d);
    assert_eq!(code, 0, "{out}");
    // answering 0 everywhere: false zeros, exit 1 even without an excess limit
    let zeros: String = text.lines().filter(|l| !l.starts_with('#')).map(|_| "0\n").collect();
    let (code, out, _, json) = judge(&text, &zeros, "f64", &[], &d);
    assert_eq!(code, 1, "{out}");
    assert_eq!(json.unwrap()["families"][0]["false_zeros"], 50 - intersecting);
}

/// Malformed, short, long or misaligned answer files are errors naming the line; `nan`,
/// `inf` and `error` answers are judged (non-finite), not rejected.
#[test]
fn malformed_and_misaligned_answers_are_line_numbered_errors() {
    let text = cases("random", 4, 9, "f64", &[]);
    let labels: Vec<&str> =
        text.lines().filter(|l| !l.starts_with('#')).map(|l| l.split(' ').next().unwrap()).collect();
    let d = dir("malformed");
    let good = "0.5\n0.5\n0.5\n0.5\n";
    let bad = [
        ("0.5\n0.5\nzero\n0.5\n", "line 3", "not a number"),
        ("0.5\n0.5\n0.5\n", "3 answers for 4 cases", ""),
        ("0.5\n0.5\n0.5\n0.5\n0.5\n", "line 5", "more answers"),
        ("0.5\n0.5 1 2\n0.5\n0.5\n", "line 2", "found 3 fields"),
        ("0.5\n0.5\n0.5\n0.5 1 2 3 4 5 x\n", "line 4", "not a number"),
    ];
    for (answers, at, what) in bad {
        let (code, out, err, _) = judge(&text, answers, "f64", &[], &d);
        assert_eq!(code, 3, "{answers:?}: {out}");
        assert!(err.contains(at) && err.contains(what), "{answers:?}: {err}");
    }
    // labels, when given, must match: a swapped pair is an error, not a silent shift
    let swapped = format!("{} 0.5\n{} 0.5\n{} 0.5\n{} 0.5\n", labels[1], labels[0], labels[2], labels[3]);
    let (code, _, err, _) = judge(&text, &swapped, "f64", &[], &d);
    assert_eq!(code, 3);
    assert!(err.contains("line 1") && err.contains("out of order"), "{err}");
    let labelled = format!(
        "{} 0.5\n# a comment\n\n{} 0.5\n{} nan\n{} error\n",
        labels[0], labels[1], labels[2], labels[3]
    );
    let (code, out, err, json) = judge(&text, &labelled, "f64", &["--max-misclassified", "4"], &d);
    assert_eq!(code, 0, "{out}{err}");
    assert_eq!(json.unwrap()["families"][0]["nonfinite"], 2);
    let (code, ..) = judge(&text, good, "f64", &["--max-excess", "1e300", "--max-misclassified", "4"], &d);
    assert_eq!(code, 0);
    // a malformed case file is named too
    let (code, _, err, _) = judge("x 1 2 3\n", good, "f64", &[], &d);
    assert_eq!(code, 3);
    assert!(err.contains("cases.txt: line 1"), "{err}");
    // verdicts
    let (code, out, _, json) =
        judge(&text, "disjoint\ndisjoint\nintersecting\ndisjoint\n", "f64", &["--query", "intersect"], &d);
    let truth: Vec<bool> = {
        let (_, o, _) = tridist(&["eval", "--kernel", "oracle", "--query", "intersect"], &text);
        o.lines().map(|l| l.ends_with("intersecting")).collect()
    };
    let wrong = usize::from(!truth[2]) + truth.iter().enumerate().filter(|(i, &t)| *i != 2 && t).count();
    assert_eq!(code, if wrong == 0 { 0 } else { 1 }, "{out}");
    let j = json.unwrap();
    let g = &j["families"][0];
    assert_eq!(
        g["contact_misses"].as_u64().unwrap() + g["strict_false_zeros"].as_u64().unwrap(),
        wrong as u64
    );
    let (code, _, err, _) =
        judge(&text, "maybe\ndisjoint\ndisjoint\ndisjoint\n", "f64", &["--query", "intersect"], &d);
    assert_eq!(code, 3);
    assert!(err.contains("line 1") && err.contains("intersecting, disjoint"), "{err}");
}

/// Bad input in a case file (a NaN or infinite coordinate) is judged, not refused: "no
/// distance" (`nan`, `error`; `invalid` for verdicts) is right, any number is wrong and named by
/// the case file's line; the finite cases are judged as before. A file of bad input only works.
#[test]
fn bad_input_in_a_case_file_is_judged() {
    let d = dir("bad-input");
    let bad = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../corpus/triangle/bad_input.cases"),
    )
    .unwrap();
    let n_bad = bad.lines().filter(|l| !l.trim().is_empty() && !l.starts_with('#')).count();
    assert!(n_bad >= 8);
    let finite = cases("random", 3, 5, "f64", &[]);
    let text = format!("{finite}{bad}");
    let exact: Vec<String> = {
        let (_, o, _) = tridist(&["eval", "--kernel", "oracle"], &finite);
        o.lines().map(|l| l.split(' ').nth(1).unwrap().to_string()).collect()
    };
    let right = format!("{}\n{}", exact.join("\n"), vec!["nan"; n_bad].join("\n"));
    let (code, out, err, json) = judge(&text, &right, "f64", &[], &d);
    assert_eq!(code, 0, "{out}{err}");
    assert!(
        out.contains(&format!("bad input (a non-finite coordinate): {n_bad} cases, 0 answered")),
        "{out}"
    );
    let j = json.unwrap();
    assert_eq!(j["cases"], 3 + n_bad as u64);
    assert_eq!(j["bad_input"]["answered_with_a_number"], 0);
    // one bad case answered with a number: wrong, and its case-file line is named
    let mut answers: Vec<String> = right.lines().map(String::from).collect();
    answers[3 + 2] = "4".into();
    let (code, out, _, json) = judge(&text, &answers.join("\n"), "f64", &[], &d);
    assert_eq!(code, 1, "{out}");
    let line = finite.lines().count()
        + bad.lines().position(|l| l.starts_with("bad_input/nan_everywhere")).unwrap()
        + 1;
    assert_eq!(json.unwrap()["bad_input"]["lines"][0], line as u64, "{out}");
    assert!(out.contains(&format!("lines {line})")), "{out}");
    // bad input only, verdicts
    let verdicts = vec!["invalid"; n_bad].join("\n");
    let (code, out, err, _) = judge(&bad, &verdicts, "f32", &["--query", "intersect"], &d);
    assert_eq!(code, 0, "{out}{err}");
    let (code, out, _, _) =
        judge(&bad, &vec!["disjoint"; n_bad].join("\n"), "f32", &["--query", "intersect"], &d);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains(&format!("{n_bad} answered with a number instead of invalid or error")), "{out}");
}
