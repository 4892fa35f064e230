//! The `tridist` command end to end: output format, malformed input, non-finite input, bad
//! arguments, bench and advise.

use std::io::Write;
use std::process::{Command, Stdio};

fn tridist(args: &[&str], stdin: &str) -> (i32, String, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_tridist"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    child.stdin.take().expect("stdin").write_all(stdin.as_bytes()).expect("write");
    let out = child.wait_with_output().expect("wait");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

const PAIRS: &str = "# comment\n\nfar 0 0 0 1 0 0 0 1 0 0 0 2 1 0 2 0 1 2\npierce 0 0 0 1 0 0 0 1 0 0.2 0.2 -1 0.2 0.2 1 5 5 0.5\n";

#[test]
fn eval_prints_label_and_shortest_round_trip_squared_distance() {
    for (prec, variant) in [("f32", "scalar"), ("f64", "auto"), ("f32", "soa")] {
        let (code, out, err) = tridist(&["eval", "--precision", prec, "--variant", variant], PAIRS);
        assert_eq!(code, 0, "{err}");
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines.len(), 2);
        let a = [[0.0f64, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let b = [[0.0f64, 0.0, 2.0], [1.0, 0.0, 2.0], [0.0, 1.0, 2.0]];
        let want = tridist::sqdist_triangle_triangle(&a, &b);
        let got: f64 = lines[0].strip_prefix("far ").expect("label first").parse().expect("a number");
        assert_eq!(got, want);
        assert_eq!(lines[1], "pierce 0.0");
    }
}

#[test]
fn eval_check_and_oracle_exact() {
    let (code, out, _) = tridist(&["eval", "--check"], PAIRS);
    assert_eq!(code, 0);
    assert!(out.lines().all(|l| l.contains(" E=")), "{out}");
    let (code, out, _) =
        tridist(&["eval", "--kernel", "oracle", "--exact"], "x 0 0 0 1 0 0 0 1 0 0 0 0.1 1 0 0.1 0 1 0.1\n");
    assert_eq!(code, 0);
    // 0.1 is not exactly 1/10 in binary: the exact square has a power-of-two denominator
    let frac = out.trim().strip_prefix("x ").expect("label");
    let (n, d) = frac.split_once('/').expect("num/den");
    let d: u128 = d.parse().expect("denominator");
    assert!(d.is_power_of_two() && n.parse::<u128>().is_ok(), "{out}");
}

#[test]
fn malformed_lines_are_reported_with_line_numbers_and_the_run_goes_on() {
    let input = "ok 0 0 0 1 0 0 0 1 0 0 0 2 1 0 2 0 1 2\nshort 1 2 3\nnan 0 0 0 1 0 0 0 1 0 0 0 NaN 1 0 2 0 1 2\nbad 0 0 0 1 0 0 0 1 0 0 0 two 1 0 2 0 1 2\n";
    let (code, out, err) = tridist(&["eval"], input);
    assert_eq!(code, 1, "malformed input must make the exit status non-zero");
    assert!(err.contains("line 2") && err.contains("line 4"), "{err}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines, vec!["ok 4.0", "nan NaN"]);
    let (_, out, _) = tridist(&["eval", "--kernel", "oracle"], "inf 0 0 0 1 0 0 0 1 0 0 0 inf 1 0 2 0 1 2\n");
    assert!(out.contains("error: non-finite"), "{out}");
}

#[test]
fn garbage_arguments_are_errors_not_panics() {
    for args in [
        &["frobnicate"][..],
        &["eval", "--variant", "avx512"],
        &["eval", "--precision", "f16"],
        &["eval", "--kernel", "penalty"],
        &["eval", "--bogus"],
        &["bench"],
        &["advise", "--scale", "-1", "--tolerance", "1"],
        &[],
    ] {
        let (code, _, err) = tridist(args, "");
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains("tridist:") && !err.contains("panicked"), "{args:?}: {err}");
    }
    let (code, out, _) = tridist(&["eval", "--list"], "");
    assert_eq!(code, 0);
    assert!(out.lines().any(|l| l == "pqp scalar f32") && out.lines().any(|l| l == "oracle exact f64"));
}

#[test]
fn bench_times_a_file_and_advise_picks_a_variant() {
    let dir = std::env::temp_dir().join(format!("tridist-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("pairs.txt");
    std::fs::write(&f, PAIRS.repeat(50)).unwrap();
    let (code, out, err) =
        tridist(&["bench", "--input", f.to_str().unwrap(), "--reps", "3", "--precision", "f32"], "");
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("100 pairs") && out.contains("queries/s"), "{out}");
    let (code, _, err) = tridist(&["bench", "--input", dir.join("missing.txt").to_str().unwrap()], "");
    assert_eq!(code, 2);
    assert!(err.contains("missing.txt"));
    let csv = dir.join("t.csv");
    std::fs::write(&csv, "workload,query,variant,precision,queries_per_second\nrandom unit cube,tri_tri,scalar,f64,100\nrandom unit cube,tri_tri,scalar,f32,200\n").unwrap();
    // f32: 8 * 2^-24 * 1e3 = 4.8e-4 > 1e-6; f64 meets it
    let (code, out, _) =
        tridist(&["advise", "--scale", "1e3", "--tolerance", "1e-6", "--csv", csv.to_str().unwrap()], "");
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("advice: scalar f64"), "{out}");
    let (code, out, _) =
        tridist(&["advise", "--scale", "1e3", "--tolerance", "1e-15", "--csv", csv.to_str().unwrap()], "");
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("no variant meets"));
}
