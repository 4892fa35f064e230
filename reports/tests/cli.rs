//! The `tridist` command end to end, as a user runs it: every kernel of the registry through
//! `eval` and `bench` (checked against the exact oracle), the output format, malformed and
//! non-finite input, bad arguments and their exit status, `advise` on a CSV, and a small
//! `report` whose CSV is parsed back and whose plots are well-formed SVG.

mod common;
use common::{number_after, tetrahedron, tmp, tridist, tridist_isa};

const PAIRS: &str = "# comment\n\nfar 0 0 0 1 0 0 0 1 0 0 0 2 1 0 2 0 1 2\npierce 0 0 0 1 0 0 0 1 0 0.2 0.2 -1 0.2 0.2 1 5 5 0.5\n";

/// Random-ish pairs of every kind: apart, piercing, touching, parallel, far from the origin.
fn mixed_pairs() -> String {
    let mut s = String::from(PAIRS);
    s.push_str("touch 0 0 0 1 0 0 0 1 0 1 0 0 2 0 0 1 1 0\n");
    s.push_str("parallel 0 0 0 1 0 0 0 1 0 0 0 0.5 1 0 0.5 0 1 0.5\n");
    s.push_str("far 1e6 1e6 1e6 1000001 1e6 1e6 1e6 1000001 1e6 1e6 1e6 1000000.25 1000001 1e6 1000000.25 1e6 1000001 1000000.25\n");
    s.push_str("skew 0.1 0.7 0.3 0.9 0.2 0.5 0.4 0.4 0.9 0.8 0.8 0.1 0.3 0.1 0.6 0.5 0.9 0.95\n");
    s
}

#[test]
fn eval_prints_label_and_shortest_round_trip_squared_distance() {
    for (prec, variant) in [("f32", "scalar"), ("f64", "auto"), ("f32", "soa")] {
        let (code, out, err) = tridist(&["eval", "--precision", prec, "--variant", variant], PAIRS);
        assert_eq!(code, 0, "{err}");
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines.len(), 2);
        let a = [[0.0f64, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let b = [[0.0f64, 0.0, 2.0], [1.0, 0.0, 2.0], [0.0, 1.0, 2.0]];
        let want: f64 = tridist::sqdist_triangle_triangle(&a, &b);
        let got: f64 = lines[0].strip_prefix("far ").expect("label first").parse().expect("a number");
        assert_eq!(got, want);
        assert_eq!(lines[1], "pierce 0.0");
    }
}

/// Every query of the registry is reachable from `eval`, in both precisions, and its answers
/// meet the bound table against the exact oracle (`--check`).
#[test]
fn every_kernel_runs_from_eval_and_agrees_with_the_oracle() {
    let input = mixed_pairs();
    let (code, list, _) = tridist(&["eval", "--list"], "");
    assert_eq!(code, 0);
    for q in tridist::Query::ALL {
        assert!(list.lines().any(|l| l == format!("{} scalar f64", q.name())), "{} not listed", q.name());
        for prec in ["f32", "f64"] {
            let mut args =
                vec!["eval", "--kernel", q.name(), "--precision", prec, "--check", "--margin", "0.3"];
            if *q == tridist::Query::Penalty {
                args.extend(["--penalty-iters", "64"]);
            }
            let (code, out, err) = tridist(&args, &input);
            assert_eq!(code, 0, "{} {prec}: {err}", q.name());
            assert_eq!(out.lines().count(), 6, "{out}");
            for l in out.lines() {
                if q.is_verdict() {
                    assert!(l.ends_with(" ok"), "{} {prec}: {l}", q.name());
                    continue;
                }
                let e: f64 = l.rsplit_once(" E=").expect("E printed").1.parse().expect("E is a number");
                // the penalty method is an approximation: its bound table row is looser
                let limit = if q.is_approximate() { 1e5 } else { 8.0 };
                assert!(e <= limit, "{} {prec}: {l}", q.name());
            }
        }
    }
    // the oracle answers the same questions
    let (code, out, _) = tridist(&["eval", "--kernel", "oracle", "--query", "intersect"], &input);
    assert_eq!(code, 0);
    assert!(out.contains("pierce intersecting") && out.contains("far disjoint"), "{out}");
}

/// `bench --tolerance correctly-rounded` times the mode and says how its pairs were decided.
#[test]
fn bench_in_the_correctly_rounded_mode_reports_its_paths() {
    let dir = tmp("bench-cr");
    let input = dir.join("pairs.txt");
    std::fs::write(&input, mixed_pairs()).unwrap();
    let (code, out, err) = tridist(
        &[
            "bench",
            "--input",
            input.to_str().unwrap(),
            "--precision",
            "f32",
            "--tolerance",
            "correctly-rounded",
        ],
        "",
    );
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("queries/s") && out.contains("correctly rounded: "), "{out}");
    assert!(out.contains(", 0 undecided"), "{out}");
}

/// `--tolerance correctly-rounded`: every line the oracle's correctly rounded square, or
/// marked `undecided` (f64 input without the `exact` feature, mostly).
#[test]
fn eval_correctly_rounded_prints_the_oracles_rounding_or_says_undecided() {
    let mut input = mixed_pairs();
    let mut x = 0.37f64;
    for i in 0..40 {
        let mut c = || {
            x = (x * 7919.0 + 0.123).fract();
            format!("{x}")
        };
        let v: Vec<String> = (0..18).map(|_| c()).collect();
        input.push_str(&format!("r{i} {}\n", v.join(" ")));
    }
    for (prec, dist) in [("f32", false), ("f64", false), ("f32", true), ("f64", true)] {
        // --distances: the square, then the distance, each the oracle's correctly rounded value
        let with = |args: &[&'static str]| {
            let mut v = args.to_vec();
            if dist {
                v.push("--distances");
            }
            v
        };
        let (code, got, err) =
            tridist(&with(&["eval", "--precision", prec, "--tolerance", "correctly-rounded"]), &input);
        assert_eq!(code, 0, "{err}");
        let (code, want, _) = tridist(&with(&["eval", "--kernel", "oracle", "--precision", prec]), &input);
        assert_eq!(code, 0);
        if dist {
            assert!(want.lines().all(|l| l.split(' ').count() == 3), "{want}");
        }
        let (mut same, mut undecided) = (0, 0);
        for (g, w) in got.lines().zip(want.lines()) {
            match g.strip_suffix(" undecided") {
                Some(_) => undecided += 1,
                None => {
                    assert_eq!(g, w, "{prec}");
                    same += 1;
                }
            }
        }
        assert_eq!(same + undecided, want.lines().count());
        // f32 is decided in f64 for these (distances: but for contacts it cannot prove); f64
        // needs the oracle for pairs not exactly representable
        if prec == "f32" && !dist {
            assert_eq!(undecided, 0, "{got}");
        }
        if prec == "f32" {
            assert!(same > want.lines().count() / 2, "{got}");
        }
    }
}

#[test]
fn eval_check_intervals_and_oracle_exact() {
    let (code, out, _) = tridist(&["eval", "--check", "--intervals"], PAIRS);
    assert_eq!(code, 0);
    // far: distance 2, squared 4, interval around 2
    let far = out.lines().next().unwrap();
    let iv = far.split_once('[').unwrap().1.split_once(']').unwrap().0;
    let (lo, hi) = iv.split_once(", ").unwrap();
    let (lo, hi): (f64, f64) = (lo.parse().unwrap(), hi.parse().unwrap());
    assert!(lo <= 2.0 && 2.0 <= hi && hi - lo < 1e-12, "{far}");
    let (code, out, _) =
        tridist(&["eval", "--kernel", "oracle", "--exact"], "x 0 0 0 1 0 0 0 1 0 0 0 0.1 1 0 0.1 0 1 0.1\n");
    assert_eq!(code, 0);
    // 0.1 is not exactly 1/10 in binary: the exact square has a power-of-two denominator
    let frac = out.trim().strip_prefix("x ").expect("label");
    let (n, d) = frac.split_once('/').expect("num/den");
    let d: u128 = d.parse().expect("denominator");
    assert!(d.is_power_of_two() && n.parse::<u128>().is_ok(), "{out}");
    let (code, _, err) = tridist(&["eval", "--exact"], PAIRS);
    assert_eq!(code, 3);
    assert!(err.contains("--kernel oracle"), "{err}");
    // the fraction is the square's: not with --distances; a peer prints squares only
    let (code, _, err) = tridist(&["eval", "--kernel", "oracle", "--exact", "--distances"], PAIRS);
    assert!(code == 3 && err.contains("not with --distances"), "{err}");
    let (code, _, err) = tridist(&["eval", "--peer", "parry3d", "--distances"], PAIRS);
    assert!(code == 3 && err.contains("--distances"), "{err}");
    // outside the correctly rounded mode the distance is the square root of the square
    let (code, out, _) = tridist(&["eval", "--distances"], PAIRS);
    assert_eq!(code, 0);
    for l in out.lines() {
        let v: Vec<f64> = l.split(' ').skip(1).map(|x| x.parse().unwrap()).collect();
        assert!(v.len() == 2 && v[0].sqrt() == v[1], "{l}");
    }
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
    assert!(out.contains("error: non-finite input"), "{out}");
    let (_, out, _) =
        tridist(&["eval", "--kernel", "intersect"], "nan 0 0 0 1 0 0 0 1 0 0 0 NaN 1 0 2 0 1 2\n");
    assert_eq!(out.trim(), "nan invalid");
}

/// `--variant avx512` answers as `avx2fma` does, bit for bit (the same fused operations on
/// wider vectors), or, on a CPU without AVX-512, is a runtime error (status 3) that says so.
#[test]
fn avx512_variant_answers_as_avx2fma_or_says_it_is_unavailable() {
    let input = "apart 0 0 0 1 0 0 0 1 0 0.25 0.25 2 1 0 2 0 1 3\ncrossing 0 0 0 1 0 0 0 1 0 0.2 0.2 -1 0.3 0.1 1 0.1 0.4 1\n";
    for p in ["f32", "f64"] {
        let (c2, o2, e2) = tridist(&["eval", "--variant", "avx2fma", "--precision", p, "--check"], input);
        let (c5, o5, e5) = tridist(&["eval", "--variant", "avx512", "--precision", p, "--check"], input);
        if !tridist::Isa::Avx2Fma.is_available() {
            continue;
        }
        assert_eq!(c2, 0, "{e2}");
        if tridist::Isa::Avx512.is_available() {
            assert_eq!((c5, &o5), (0, &o2), "{e5}");
            assert_eq!(o5.lines().count(), 2, "{o5}");
        } else {
            assert_eq!(c5, 3, "{e5}");
            assert!(e5.contains("avx512") && e5.contains("not available"), "{e5}");
        }
    }
}

#[test]
fn usage_errors_exit_2_with_the_usage_and_runtime_errors_exit_3_without() {
    for args in [
        &["frobnicate"][..],
        &["eval", "--variant", "avx1024"],
        &["eval", "--precision", "f16"],
        &["eval", "--kernel", "pqq"],
        &["eval", "--bogus"],
        &["eval", "--tolerance", "abs:-1"],
        &["eval", "--margin", "nan"],
        &["bench"],
        &["advise", "--scale", "-1", "--tolerance", "1"],
    ] {
        let (code, _, err) = tridist(args, "");
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(
            err.contains("error:") && (err.contains("Usage") || err.contains("--help")),
            "{args:?}: {err}"
        );
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
    // a negative number is a value the option rejects, not an unknown flag
    for args in [
        &["advise", "--scale", "-1", "--tolerance", "1"][..],
        &["advise", "--scale", "1", "--tolerance", "-1e-3"],
        &["eval", "--kernel", "within", "--margin", "-0.5"],
        &["eval", "--kernel", "penalty", "--penalty-tol", "-1"],
        &["judge", "--cases", "c", "--answers", "a", "--precision", "f32", "--max-excess", "-1"],
        // integer options alike (they said "unexpected argument '-1' found")
        &["eval", "--threads", "-1"],
        // and the certificate's tolerance (it said "unexpected argument '-1' found")
        &["eval", "--tolerance", "-1"],
        &["bench", "--input", "x", "--tolerance", "-2"],
        &["eval", "--kernel", "penalty", "--penalty-iters", "-3"],
        &["bench", "--input", "x", "--reps", "-2"],
        &["cases", "--count", "-1"],
        &["cases", "--seed", "-5"],
        &["judge", "--cases", "c", "--answers", "a", "--precision", "f32", "--max-misclassified", "-1"],
        &["mesh", "a", "b", "--show", "-1"],
        &["mesh", "a", "b", "--max-contacts", "-1"],
        &["mesh", "a", "b", "--leaf", "-1"],
        &["mesh", "a", "b", "--width", "-4"],
        &["report", "--pairs", "-4"],
    ] {
        let (code, _, err) = tridist(args, "");
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains("invalid value '-") && !err.contains("unexpected argument"), "{args:?}: {err}");
    }
    let (code, _, err) = tridist(&[], "");
    assert_eq!(code, 2);
    assert!(err.contains("Usage: tridist <COMMAND>") && err.contains("Exit status"), "{err}");
    // the registry's names are listed
    let (_, _, err) = tridist(&["eval", "--kernel", "pqq"], "");
    assert!(err.contains("unknown query"), "{err}");
    let (code, _, err) = tridist(&["eval", "--kernel", "within"], PAIRS);
    assert_eq!(code, 3);
    assert!(err.contains("--margin") && !err.contains("Usage"), "{err}");
    let (code, out, _) = tridist(&["eval", "--help"], "");
    assert_eq!(code, 0);
    assert!(out.contains("--tolerance") && out.contains("--penalty-iters"));
}

#[test]
fn bench_times_every_kernel_and_a_peer() {
    let dir = tmp("bench");
    let f = dir.join("pairs.txt");
    std::fs::write(&f, mixed_pairs().repeat(40)).unwrap();
    for q in tridist::Query::ALL {
        let (code, out, err) = tridist(
            &[
                "bench",
                "--input",
                f.to_str().unwrap(),
                "--kernel",
                q.name(),
                "--reps",
                "2",
                "--precision",
                "f32",
                "--margin",
                "0.1",
            ],
            "",
        );
        assert_eq!(code, 0, "{}: {err}", q.name());
        assert!(
            out.contains("240 pairs") && out.contains("queries/s") && out.contains("paths of one pass"),
            "{out}"
        );
    }
    let (code, out, err) =
        tridist(&["bench", "--input", f.to_str().unwrap(), "--peer", "parry3d", "--reps", "2"], "");
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("parry3d f64") && out.contains("agreement"), "{out}");
    let (code, _, err) = tridist(&["bench", "--input", dir.join("missing.txt").to_str().unwrap()], "");
    assert_eq!(code, 3);
    assert!(err.contains("missing.txt") && !err.contains("Usage"), "{err}");
    std::fs::write(dir.join("empty.txt"), "# nothing\n").unwrap();
    let (code, _, err) = tridist(&["bench", "--input", dir.join("empty.txt").to_str().unwrap()], "");
    assert_eq!(code, 3);
    assert!(err.contains("no pairs"), "{err}");
}

#[test]
fn advise_reads_the_csv_and_picks_a_variant() {
    let dir = tmp("advise");
    let csv = dir.join("t.csv");
    let head = "workload,query,implementation,precision,threads,tolerance,outputs,stages,queries_per_second,pairs,prefiltered,delegated,refined,recertified,compacted,widened,exact,uncertified\n";
    // (rows with closest points and without the quick stage first: advise reads the default
    // engine's answer-only figure)
    std::fs::write(&csv, format!("{head}random,tri_tri,scalar,f64,1,default,points,quick,999,1,0,0,0,0,0,0,0,0\nrandom,tri_tri,scalar,f64,1,default,answer,full,998,1,0,0,1,0,0,0,0,0\nrandom,tri_tri,scalar,f64,1,default,answer,quick,100,1,0,0,0,0,0,0,0,0\nrandom,tri_tri,scalar,f32,1,default,answer,quick,200,1,0,0,0,0,0,0,0,0\n")).unwrap();
    // f32: 8 * 2^-24 * 1e3 = 4.8e-4 > 1e-6; f64 meets it
    let (code, out, _) =
        tridist(&["advise", "--scale", "1e3", "--tolerance", "1e-6", "--csv", csv.to_str().unwrap()], "");
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("advice: scalar f64"), "{out}");
    assert!(out.contains("; 100 queries/s") && !out.contains("999") && !out.contains("998"), "{out}");
    let (code, out, _) =
        tridist(&["advise", "--scale", "1e3", "--tolerance", "1e-15", "--csv", csv.to_str().unwrap()], "");
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("no variant meets"));
    // beyond f32's range, f32 says why it does not fit, although at S = 1e39 its bound alone
    // would (E * 2^-24 * 1e39 is about 3.4e32 <= 1e33 for E near 6; it said only "does not
    // meet it")
    for (scale, tol, why) in [
        ("1e39", "1e33", "does not meet it (squared distances overflow f32 beyond S = 5e18)"),
        ("1e-30", "1e-30", "does not meet it (distances below 3.7e-23 square to 0 in f32)"),
    ] {
        let (code, out, _) =
            tridist(&["advise", "--scale", scale, "--tolerance", tol, "--csv", csv.to_str().unwrap()], "");
        assert_eq!(code, 0, "{out}");
        let f32_lines: Vec<&str> = out.lines().filter(|l| l.contains(" f32: declared")).collect();
        assert!(!f32_lines.is_empty() && f32_lines.iter().all(|l| l.ends_with(why)), "{out}");
        assert!(out.contains("advice: scalar f64"), "{out}");
    }
    std::fs::write(&csv, "not,a,throughput,table\n").unwrap();
    let (code, _, err) =
        tridist(&["advise", "--scale", "1", "--tolerance", "1", "--csv", csv.to_str().unwrap()], "");
    assert_eq!(code, 3);
    assert!(err.contains("header"), "{err}");
    // a rate that is not a measurement, or an unknown precision, is an error with its line
    // (NaN was printed as "NaN queries/s" and ranked; "f33" rows were skipped silently)
    for (row, says) in [
        (
            "random,tri_tri,scalar,f64,1,default,answer,quick,NaN,1,0,0,0,0,0,0,0,0",
            ":2: queries_per_second \"NaN\"",
        ),
        ("random,tri_tri,scalar,f33,1,default,answer,quick,100,1,0,0,0,0,0,0,0,0", ":2: precision \"f33\""),
    ] {
        std::fs::write(&csv, format!("{head}{row}\n")).unwrap();
        let (code, out, err) =
            tridist(&["advise", "--scale", "1", "--tolerance", "1", "--csv", csv.to_str().unwrap()], "");
        assert_eq!(code, 3, "{out}");
        assert!(err.contains(says) && out.is_empty(), "{err}");
    }
}

/// A small report end to end: every file is written, the CSV parses back with the csv crate
/// and names every query, the plots are complete SVG documents with their legends.
#[test]
fn a_small_report_writes_parseable_files() {
    let dir = tmp("report");
    let (code, _, err) = tridist(
        &[
            "report",
            "--out",
            dir.to_str().unwrap(),
            "--cases",
            "12",
            "--pairs",
            "64",
            "--budget-ms",
            "1",
            "--mesh-poses",
            "3",
            "--mesh-scale",
            "1",
        ],
        "",
    );
    assert_eq!(code, 0, "{err}");
    assert!(err.contains(&format!("wrote the reports to {}", dir.display())), "{err}");
    for f in ["ACCURACY.md", "THROUGHPUT.md", "TRADEOFF.md", "MESH.md"] {
        let t = std::fs::read_to_string(dir.join(f)).unwrap();
        let features = if cfg!(feature = "all-variants") { " --features all-variants" } else { "" };
        assert!(
            t.starts_with(&format!(
                "<!-- Generated by `cargo run --release -p tridist-reports{features} -- report --cases 12"
            )),
            "{f}"
        );
        assert!(!t.contains("EXCEEDED") && !t.contains("**NO**"), "{f} reports a bound exceeded");
    }
    // the mesh table: both ends of the trajectory apart, its middle through the armadillo,
    // the libraries agreeing (FCL when it was built)
    let mesh = std::fs::read_to_string(dir.join("MESH.md")).unwrap();
    let fcl = tridist_scenes::mesh_peer::MeshLib::Fcl.available();
    for p in ["## tridist f32", "## tridist f64"] {
        let rows: Vec<Vec<&str>> = mesh
            .split(p)
            .nth(1)
            .expect("a section per precision")
            .lines()
            .filter(|l| l.starts_with("| +") || l.starts_with("| -"))
            .take(3)
            .map(|r| r.split('|').map(str::trim).collect())
            .collect();
        assert_eq!(rows.len(), 3, "{mesh}");
        for (k, cells) in rows.iter().enumerate() {
            let through = k == 1;
            let d = cells[2].parse::<f64>().unwrap();
            // 3 units apart: a gap; in the middle: touching, and contacts within the margin
            assert!(if through { d == 0.0 } else { d > 0.5 }, "{cells:?}");
            let v = if through { "yes" } else { "no" };
            let verdicts = if fcl { format!("{v}, {v}, {v}") } else { format!("{v}, -, {v}") };
            assert_eq!(cells[8], verdicts, "{cells:?}");
            assert_eq!(cells[12].parse::<usize>().unwrap() > 0, through, "{cells:?}");
            assert_eq!(cells[4].parse::<f64>().is_ok_and(|t| t > 0.0), fcl, "{cells:?}"); // FCL's time
                                                                                          // the clearance check within the contacts' margin: yes exactly where they are
            assert_eq!(cells[15], v, "{cells:?}");
            assert!(cells[16].parse::<f64>().unwrap() >= 0.0, "{cells:?}");
            assert_eq!(cells[17], "ok", "{cells:?}");
        }
    }
    // near contact: one row per placement (the poses asked for), each placed at the gap, apart,
    // the libraries agreeing
    let near: Vec<&str> = mesh
        .split("## Near contact at random orientations")
        .nth(1)
        .expect("the near-contact section")
        .split("\n## ")
        .next()
        .unwrap_or_default()
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| placement"))
        .collect();
    assert_eq!(near.len(), 3, "{mesh}");
    for r in near {
        let cells: Vec<&str> = r.split('|').map(str::trim).collect();
        let d: f64 = cells[2].parse().unwrap();
        assert!((0.999_999e-3..=1.000_001e-3).contains(&d), "{r}");
        assert!(cells[3].parse::<f64>().unwrap() > 0.0 && cells[4].parse::<f64>().unwrap() > 0.0, "{r}");
        assert_eq!(cells[5].parse::<f64>().is_ok_and(|t| t > 0.0), fcl, "{r}"); // FCL's time
        assert_eq!(cells[8], if fcl { "no, no" } else { "no, -" }, "{r}");
        // the pair at the gap (1e-3) is within the margin (0.02): at least one contact
        assert!(cells[12].parse::<usize>().unwrap() >= 1, "{r}");
        assert!(cells[13..15].iter().all(|x| x.parse::<f64>().unwrap() >= 0.0), "{r}");
        // the kernels alone on those contacts' pairs: timed (there is at least one), and
        // giving each contact's distance (checked in the agreement column)
        assert!(cells[15].parse::<f64>().unwrap() > 0.0, "{r}");
        // and so the clearance check at that margin says yes
        assert_eq!(cells[16], "yes", "{r}");
        assert!(cells[17..19].iter().all(|x| x.parse::<f64>().unwrap() >= 0.0), "{r}");
        assert_eq!(cells[19], "ok", "{r}");
    }
    // two threads on the contact query at the middle pose, with the two independent workers'
    // ceiling, per precision: both speed-ups measured (positive ratios)
    let ratio = |s: &str| s.trim_end_matches('x').parse::<f64>().is_ok_and(|r| r > 0.0);
    let scaling: Vec<(&str, &str)> = mesh
        .split("Contacts on two threads at the pose with the most contacts: **")
        .skip(1)
        .map(|s| {
            let (two, rest) =
                s.split_once("** one thread's speed (two independent one-thread workers: ").unwrap();
            (two, rest.split_once(')').unwrap().0)
        })
        .collect();
    assert_eq!(scaling.len(), 2, "{mesh}");
    assert!(scaling.iter().all(|(two, apart)| ratio(two) && ratio(apart)), "{scaling:?}");
    // tree widths 2, 4 and 8, leaf sizes 2, 4, 6 and 8, per precision: every time positive
    // where it must be, each ratio the default's time over the row's (as printed, within
    // the cells' rounding)
    for (section, label, want) in [
        ("## Tree width", "width", &["2", "4", "8"][..]),
        ("## Leaf size", "leaf", &["2", "4", "6", "8"][..]),
    ] {
        let text = mesh.split(section).nth(1).unwrap_or_else(|| panic!("no {section} in {mesh}"));
        for p in ["f32", "f64"] {
            let rows: Vec<Vec<&str>> = text
                .lines()
                .skip_while(|l| !l.starts_with(&format!("| {p} {label}")))
                .skip(2)
                .take_while(|l| l.starts_with("| "))
                .map(|l| l.split('|').map(str::trim).collect())
                .collect();
            assert_eq!(rows.iter().map(|c| c[1]).collect::<Vec<_>>(), want, "{text}");
            let num = |x: &str| x.trim_end_matches('x').parse::<f64>().unwrap();
            let def = rows.iter().find(|c| c[1] == "4").unwrap();
            for c in &rows {
                // build, distance and the near-contact distance and contacts take time; the
                // others may round to 0
                assert!([c[3], c[4], c[7], c[9]].iter().all(|x| num(x) > 0.0), "{c:?}");
                assert!(c[5..10].iter().all(|x| num(x) >= 0.0), "{c:?}");
                // (times printed to 0.001 ms, ratios to 0.01)
                for (r, t) in [(10, 3), (11, 4), (12, 7), (13, 9)] {
                    let (lo, hi) = (
                        (num(def[t]) - 5e-4) / (num(c[t]) + 5e-4),
                        (num(def[t]) + 5e-4) / (num(c[t]) - 5e-4),
                    );
                    let got = num(c[r]);
                    assert!(
                        lo - 0.005 <= got && got <= hi + 0.005,
                        "{label} {}: {got} outside [{lo}, {hi}]",
                        c[1]
                    );
                }
                if c[1] == "4" {
                    assert!(c[10..14].iter().all(|x| *x == "1.00x"), "{c:?}");
                }
            }
        }
    }
    // TrueForm's protocol: per pair, tridist in both precisions and a row per C++ mesh peer,
    // measured exactly when that peer was built, its distances agreeing with tridist f64's
    // (float within float's rounding of a [-1, 1]^3 scene), on 4 x 3 placements
    let protocol = mesh.split("## TrueForm's protocol").nth(1).expect("the protocol section");
    let protocol = protocol.split("\n## ").next().unwrap();
    let pairs: Vec<&str> = protocol.split("\n### ").skip(1).collect();
    assert_eq!(pairs.len(), 2, "{protocol}");
    for pair in pairs {
        peer_table(pair, 12);
    }
    // every peer on the trajectory (3 poses) and at near contact (5 gaps, 2 placements each)
    let every = mesh.split("## Every peer on the trajectory").nth(1).expect("the every-peer section");
    let every = every.split("\n## ").next().unwrap();
    let tables: Vec<&str> = every.split("\n### ").skip(1).collect();
    assert_eq!(tables.len(), 2, "{every}");
    assert!(tables[0].starts_with("the trajectory (3 placements)"), "{}", tables[0]);
    assert!(tables[1].starts_with("near contact (10 placements)"), "{}", tables[1]);
    for table in tables {
        peer_table(table, if table.starts_with("near") { 10 } else { 3 });
    }
    // the scale section: the Armadillo at 52,000 and 208,000 triangles per mesh (`--mesh-scale 1`), each
    // with tridist's two rows and built peers agreeing with it, every build timed
    let scale = mesh.split("## Scale").nth(1).expect("the scale section").split("\n## ").next().unwrap();
    let levels: Vec<&str> = scale.split("\n### ").skip(1).collect();
    assert_eq!(levels.len(), 2, "{scale}");
    for (level, want) in levels.iter().zip(["52000", "208000"]) {
        assert!(level.starts_with(&format!("{want} triangles per mesh")), "{level}");
        let rows: Vec<Vec<&str>> = level
            .lines()
            .filter(|l| l.starts_with("| ") && !l.starts_with("| library"))
            .map(|l| l.split(" | ").map(|c| c.trim_matches(['|', ' '])).collect())
            .collect();
        assert_eq!(rows.len(), 6, "{level}");
        for r in &rows {
            if r[1].starts_with("not built") {
                continue;
            }
            assert_eq!(r.len(), 11, "{r:?}");
            if !r[0].contains("default threads") {
                assert!(r[10].parse::<f64>().unwrap() > 0.0, "{r:?}: no build time");
            }
            if r[0].starts_with("FCL") || r[0].starts_with("Coal") {
                assert_eq!(r[8], "0 of 3", "{r:?}");
            }
        }
    }
    // builds, per precision: both timed, tridist's share of parry3d's time as stated
    for p in ["## tridist f32", "## tridist f64"] {
        let line =
            mesh.split(p).nth(1).and_then(|s| s.lines().find(|l| l.starts_with("Tree build"))).unwrap();
        let num = |after: &str| -> f64 {
            let s = line.split(after).nth(1).unwrap_or_else(|| panic!("{after:?} in {line}"));
            s.split([' ', 'x']).next().unwrap().parse().unwrap()
        };
        let (ours, parry, share) = (num("): tridist "), num(", parry3d "), num("(tridist takes "));
        assert!(ours > 0.0 && parry > 0.0, "{line}");
        assert!((share - ours / parry).abs() <= 0.01, "{line}");
    }
    // threads: both precisions of both workloads at the run's batch and the large one
    let thr = std::fs::read_to_string(dir.join("THROUGHPUT.md")).unwrap();
    let rows = section_rows(&thr, "## Threads");
    assert_eq!(rows.len(), 8, "{thr}");
    // its paragraph states the engine's own splitting parameters, read from the library
    let para = thr.split("## Threads").nth(1).and_then(|t| t.split("\n\n").nth(1)).unwrap();
    let (min, piece) = (tridist::Engine::MIN_PARALLEL, tridist::Engine::PIECE);
    assert!(
        para.contains(&format!(
            "batches of at least {min} pairs split into pieces of at least {piece} pairs"
        )),
        "{para}"
    );
    assert!(para.contains(&format!("(up to {} µs)", tridist::Engine::WAIT_AWAKE.as_micros())), "{para}");
    for c in &rows {
        assert!(c[3] == "64" || c[3] == "65536", "{c:?}");
        assert!(c[4..6].iter().all(|x| x.parse::<f64>().unwrap() > 0.0), "{c:?}");
        assert!(c[6].ends_with('x') && c[7].ends_with('x'), "{c:?}");
    }
    // triangle distance with closest points (like for like with FCL): both precisions of both
    // FCL workloads, tridist's figures with and without points measured (FCL's only with it)
    let pts = section_rows(&thr, "## With closest points");
    assert_eq!(pts.len(), 4, "{thr}");
    for c in &pts {
        assert!(c[3..5].iter().all(|x| x.parse::<f64>().unwrap() > 0.0), "{c:?}");
    }
    // and without the quick stage: the same rows, each figure positive and its speed-up a ratio
    let full = section_rows(&thr, "## Without the quick stage");
    assert_eq!(full.len(), 4, "{thr}");
    for c in &full {
        assert!(c[3..5].iter().all(|x| x.parse::<f64>().unwrap() > 0.0), "{c:?}");
        assert!(c[5].ends_with('x') && c[5].trim_end_matches('x').parse::<f64>().unwrap() > 0.0, "{c:?}");
    }
    let mut r = csv::Reader::from_path(dir.join("throughput.csv")).unwrap();
    assert_eq!(r.headers().unwrap().len(), 19);
    let rows: Vec<csv::StringRecord> = r.records().map(|x| x.unwrap()).collect();
    for q in tridist::Query::ALL {
        assert!(rows.iter().any(|x| &x[1] == q.name()), "{}", q.name());
    }
    assert!(rows.iter().all(|x| x.len() == 19 && x[8].parse::<f64>().unwrap() > 0.0));
    // the correctly rounded mode judged per family: every certified answer RN(D*) (and its
    // distance RN(sqrt(D*))); asking for distances never decides more pairs
    let acc = std::fs::read_to_string(dir.join("ACCURACY.md")).unwrap();
    let cr_rows = section_rows(&acc, "## Correctly rounded answers");
    assert!(cr_rows.len() >= 2 * tridist_scenes::Family::ALL.len() - 2, "{acc}");
    let pct = |x: &str| if x == "0" { 0.0 } else { x.trim_end_matches('%').parse::<f64>().unwrap() };
    assert!(cr_rows.iter().all(|c| c.len() == 11 && c[9] == "0" && pct(c[8]) >= pct(c[7])), "{cr_rows:?}");
    // the correctly rounded mode is measured in both precisions, its undecided pairs counted
    let cr: Vec<_> = rows.iter().filter(|x| &x[5] == "correctly-rounded").collect();
    assert!(
        cr.iter().any(|x| &x[3] == "f32") && cr.iter().any(|x| &x[3] == "f64"),
        "no correctly rounded rows"
    );
    let knob = section_rows(&thr, "## The tolerance knob");
    assert!(
        knob.iter()
            .any(|c| c[3] == "correctly-rounded" && c[4].parse::<f64>().unwrap() > 0.0 && c.len() == 13),
        "{thr}"
    );
    assert!(rows.iter().any(|x| &x[1] == "tri_tri" && &x[6] == "points"), "no row with closest points");
    assert!(rows.iter().any(|x| &x[1] == "tri_tri" && &x[7] == "full"), "no row without the quick stage");
    for f in ["tradeoff.svg", "magnitude.svg", "offset.svg", "penalty.svg"] {
        let t = std::fs::read_to_string(dir.join(f)).unwrap();
        assert!(t.starts_with("<svg") && t.trim_end().ends_with("</svg>"), "{f}");
        assert!(t.contains("target E = 8"), "{f}: no legend");
    }
    let t = std::fs::read_to_string(dir.join("tradeoff.svg")).unwrap();
    assert!(t.contains("tridist avx2fma f32") || !tridist::Isa::Avx2Fma.is_available());
    // every peer is on the picture, even with an infinite E (drawn at the cap, said in the legend)
    assert!(t.contains("parry3d f64") && t.contains("parry3d f32"), "a peer is missing from tradeoff.svg");
}

/// The cells of the table of the section of `md` headed `heading`: its rows after the heading
/// line, a blank line, the section's paragraph, a blank line, the header and the separator.
fn section_rows<'a>(md: &'a str, heading: &str) -> Vec<Vec<&'a str>> {
    md.split(heading)
        .nth(1)
        .unwrap_or_else(|| panic!("no section {heading}"))
        .lines()
        .skip(6)
        .take_while(|l| l.starts_with("| "))
        .map(|l| l.split('|').map(str::trim).collect())
        .collect()
}

/// A reader that stops early (`tridist cases ... | head -1`) ends the command quietly with
/// status 0: no panic message, no error.
#[test]
fn closed_standard_output_ends_quietly() {
    use std::io::{BufRead, BufReader};
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_tridist"))
        .args(["cases", "--family", "all", "--count", "20000", "--seed", "1"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let mut first = String::new();
    BufReader::new(child.stdout.take().expect("stdout")).read_line(&mut first).expect("one line");
    assert!(!first.is_empty());
    // the reader is dropped here: the pipe is closed while the command still writes
    let out = child.wait_with_output().expect("wait");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(err.is_empty(), "{err}");
}

/// `tridist mesh` on two small OFF files: the distance of two unit tetrahedra 2 apart along x,
/// an intersection once moved into each other, contacts, the closest point, negative numbers
/// and axes of any length in poses, and clear errors for a malformed file, a bad pose (a zero
/// axis, a translation beyond f32's range) and a bad margin.
#[test]
fn mesh_subcommand_answers_and_rejects_bad_input() {
    let (a, bad) = (tetrahedron("mesh"), tmp("mesh").join("bad.off"));
    let a = a.as_str();
    std::fs::write(&bad, "OFF\n4 4 0\n0 0 0\n1 0 0\n").unwrap();
    for prec in ["f32", "f64"] {
        let (code, out, err) = tridist(
            &[
                "mesh",
                a,
                a,
                "--pose-b",
                "3,0,0",
                "--margin",
                "2.5",
                "--point",
                "5,0,0",
                "--precision",
                prec,
                "--show",
                "20",
            ],
            "",
        );
        assert_eq!(code, 0, "{err}");
        // the clearance check names one of the contacts (all 12 shown)
        let pair = out.split("within 2.5: yes (triangles ").nth(1).and_then(|r| r.split(';').next());
        let pair = pair.unwrap_or_else(|| panic!("no clearance line: {out}"));
        assert!(contact_lines(&out).iter().any(|c| c.0 == pair), "{pair} is not a contact: {out}");
        // below the distance (2): none, and no contacts
        let (code, below, err) =
            tridist(&["mesh", a, a, "--pose-b", "3,0,0", "--margin", "1.99", "--precision", prec], "");
        assert_eq!(code, 0, "{err}");
        assert!(below.contains("within 1.99: no ("), "{below}");
        assert_eq!(number_after(&below, "contacts within 1.99: "), 0.0, "{below}");
        // the face x = 0 of the moved copy against the vertex (1, 0, 0): distance 2
        assert_eq!(number_after(&out, "distance: "), 2.0, "{out}");
        assert!(out.contains("intersect: no"), "{out}");
        // within 2.5: the three triangles of the first holding (1, 0, 0) against the three of
        // the second holding (3, 0, 0) (distance 2) and against its slanted face (distance
        // sqrt(4.5)); the first's face x = 0 is 3 away: 12 pairs
        assert_eq!(number_after(&out, "contacts within 2.5: "), 12.0, "{out}");
        assert!(out.contains("closest point of the second mesh: 4 0 0 at 1 "), "{out}");
    }
    // every tree shape gives the same answers; the trees' node counts say the shape was used
    // (4 triangles: one leaf of up to 8 or 4, or a binary tree of 7 nodes for leaves of 1)
    let args = ["mesh", a, a, "--pose-b", "3,0,0", "--margin", "2.5", "--point", "5,0,0"];
    let (_, plain, _) = tridist(&args, "");
    for (shape, nodes) in [(["--width", "2", "--leaf", "1"], 7), (["--width", "8", "--leaf", "8"], 1)] {
        let (code, out, err) = tridist(&[&args[..], &shape[..]].concat(), "");
        assert_eq!(code, 0, "{shape:?}: {err}");
        let head = format!("meshes: 4 triangles ({nodes} nodes), 4 triangles ({nodes} nodes; trees of width {}, leaves of {});", shape[1], shape[3]);
        assert!(out.starts_with(&head), "{shape:?}: {out}");
        // the same lines after the first, bar the times
        let answers = |o: &str| -> Vec<String> {
            o.lines().skip(1).filter(|l| !l.contains(" ms")).map(String::from).collect()
        };
        assert_eq!(answers(&out), answers(&plain), "{shape:?}");
        assert_eq!(number_after(&out, "contacts within 2.5: "), 12.0, "{out}");
    }
    for (flag, bad, says) in [
        ("--leaf", "0", "1 to 8 triangles"),
        ("--leaf", "9", "1 to 8 triangles"),
        ("--leaf", "x", "invalid digit"),
        ("--width", "1", "2 to 8 children"),
        ("--width", "-2", "invalid digit"),
    ] {
        let (code, out, err) = tridist(&["mesh", a, a, flag, bad], "");
        assert_eq!(code, 2, "{flag} {bad}: {err}");
        assert!(out.is_empty() && err.contains(flag) && err.contains(says), "{flag} {bad}: {out}{err}");
    }
    // --max-contacts keeps the closest: the three pairs at distance 2 of the 12, said as a floor
    let (code, out, err) =
        tridist(&["mesh", a, a, "--pose-b", "3,0,0", "--margin", "2.5", "--max-contacts", "3"], "");
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("contacts within 2.5: 3 or more (stopped at --max-contacts;"), "{out}");
    let kept = contact_lines(&out);
    assert_eq!(kept.len(), 3, "{out}");
    assert!(kept.iter().all(|c| c.1 == 2.0), "{out}");
    let (code, out, _) = tridist(&["mesh", a, a, "--pose-b", "0.25,0.25,0.25"], "");
    assert_eq!(code, 0);
    assert!(out.contains("intersect: yes"), "{out}");
    assert!(out.contains("distance: 0 "), "{out}");
    let (code, _, err) = tridist(&["mesh", a, bad.to_str().unwrap()], "");
    assert_eq!(code, 3, "{err}");
    assert!(err.matches("bad.off").count() == 1 && err.contains("OFF"), "{err}");
    let (code, _, err) = tridist(&["mesh", a, a, "--pose-b", "1,2"], "");
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("3 or 7 numbers"), "{err}");
    let (code, _, err) = tridist(&["mesh", a, "/nonexistent.off"], "");
    assert_eq!(code, 3, "{err}");
    // negative numbers are values, not flags: the copy 3 below along x, its face x = 0 at
    // -3 against the first's vertex (0, 0, 0)... and the point (-5, 0, 0) 2 from (-3, 0, 0)
    let (code, out, err) = tridist(&["mesh", a, a, "--pose-b", "-3,0,0", "--point", "-5,0,0"], "");
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("distance: 2 "), "{out}");
    assert!(out.contains("closest point of the second mesh: -3 0 0 at 2 "), "{out}");
    // a rotation's axis of any length, a tiny one included: a quarter turn about x takes the
    // copy's vertex (0, 1, 0) to (0, 0, 1), moved by 3 along z to (0, 0, 4); (0, 0, 5) is 1 away
    for axis in ["1,0,0", "1e-200,0,0", "1e200,0,0"] {
        let pose = format!("0,0,3,{axis},90");
        let (code, out, err) = tridist(&["mesh", a, a, "--pose-b", &pose, "--point", "0,0,5"], "");
        assert_eq!(code, 0, "{err}");
        let line =
            out.lines().find(|l| l.starts_with("closest point of the second mesh: ")).expect("a point line");
        let at: Vec<f64> = line.split_whitespace().skip(6).take(3).map(|x| x.parse().unwrap()).collect();
        assert!(at.iter().zip([0.0, 0.0, 4.0]).all(|(x, w)| (x - w).abs() < 1e-12), "{axis}: {out}");
    }
    // usage errors (exit 2) before any work: a zero axis, a negative, NaN or infinite margin
    let (code, out, err) = tridist(&["mesh", a, a, "--pose-b", "0,0,3,0,0,0,90"], "");
    assert_eq!(code, 2, "{err}");
    assert!(out.is_empty() && err.contains("non-zero axis"), "{out}{err}");
    for m in ["-1", "nan", "inf", "x"] {
        let (code, out, err) = tridist(&["mesh", a, a, "--margin", m], "");
        assert_eq!(code, 2, "{m}: {err}");
        assert!(out.is_empty() && err.contains("--margin"), "{m}: {out}{err}");
    }
    // a translation beyond f32's range: an error in f32, an answer in f64
    let (code, _, err) = tridist(&["mesh", a, a, "--pose-b", "1e39,0,0", "--precision", "f32"], "");
    assert_eq!(code, 3, "{err}");
    assert!(err.contains("--pose-b") && err.contains("f32"), "{err}");
    let (code, out, err) = tridist(&["mesh", a, a, "--pose-b", "1e39,0,0"], "");
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("intersect: no"), "{out}");
}

/// The lines `tridist mesh` prints for the contacts: `tri_a tri_b distance | p | q`.
fn contact_lines(out: &str) -> Vec<(String, f64, String)> {
    out.lines()
        .filter(|l| l.starts_with("  "))
        .map(|l| {
            let (head, points) = l.trim().split_once(" | ").expect("a contact line");
            let w: Vec<&str> = head.split_whitespace().collect();
            assert_eq!(w.len(), 3, "{l}");
            (format!("{} {}", w[0], w[1]), w[2].parse().unwrap(), points.to_string())
        })
        .collect()
}

/// `--pose-a` moves the first mesh (the same answers as the opposite `--pose-b`, the points in
/// the world frame) and `--show` prints that many contacts, the closest first.
#[test]
fn mesh_pose_a_and_show() {
    let a = tetrahedron("mesh-pose-a");
    let a = a.as_str();
    let run = |args: &[&str]| {
        let (code, out, err) = tridist(&[&["mesh", a, a, "--margin", "2.5"][..], args].concat(), "");
        assert_eq!(code, 0, "{args:?}: {err}");
        out
    };
    let (moved_b, moved_a) = (run(&["--pose-b", "3,0,0"]), run(&["--pose-a", "-3,0,0"]));
    for out in [&moved_b, &moved_a] {
        assert!(out.contains("distance: 2 (squared 4)") && out.contains("contacts within 2.5: 12 "), "{out}");
    }
    // the same pair, three units further left when the first mesh moves instead
    assert!(moved_b.contains("closest points: 1 0 0 | 3 0 0"), "{moved_b}");
    assert!(moved_a.contains("closest points: -2 0 0 | 0 0 0"), "{moved_a}");
    // both poses at once: only their difference counts
    let both = run(&["--pose-a", "-1,0,0", "--pose-b", "2,0,0"]);
    assert!(
        both.contains("distance: 2 (squared 4)") && both.contains("closest points: 0 0 0 | 2 0 0"),
        "{both}"
    );
    // the default shows 10 of the 12; --show 2 the first two of them; --show 0 none
    let all = contact_lines(&moved_a);
    assert_eq!(all.len(), 10, "{moved_a}");
    assert!(all.windows(2).all(|w| w[0].1 <= w[1].1), "closest first: {moved_a}");
    assert_eq!(all[0].1, 2.0, "{moved_a}");
    let two = contact_lines(&run(&["--pose-a", "-3,0,0", "--show", "2"]));
    assert_eq!(two, all[..2], "--show 2");
    let none = run(&["--pose-a", "-3,0,0", "--show", "0"]);
    assert!(contact_lines(&none).is_empty() && none.contains("contacts within 2.5: 12 "), "{none}");
}

/// `eval --threads` answers a batch large enough to be split (at least
/// `Engine::MIN_PARALLEL` pairs) exactly as one thread does; 0 means every core.
#[test]
fn eval_threads_give_one_threads_answers() {
    let n = (tridist::Engine::MIN_PARALLEL / 11 + 1).to_string();
    let (code, cases, err) = tridist(&["cases", "--count", &n, "--seed", "3", "--precision", "f32"], "");
    assert_eq!(code, 0, "{err}");
    let pairs = cases.lines().filter(|l| !l.is_empty() && !l.starts_with('#')).count();
    assert!(pairs >= tridist::Engine::MIN_PARALLEL, "{pairs} pairs");
    let mut answers = Vec::new();
    for threads in ["1", "2", "0"] {
        let (code, out, err) = tridist(&["eval", "--precision", "f32", "--threads", threads], &cases);
        assert_eq!(code, 0, "--threads {threads}: {err}");
        assert_eq!(out.lines().count(), pairs, "--threads {threads}");
        answers.push(out);
    }
    assert!(answers.iter().all(|a| *a == answers[0]), "answers differ between thread counts");
}

/// `--variant auto` (the default) runs the variant `TRIDIST_ISA` names, as `Engine::auto` does;
/// unset, the best one; a name that is no usable variant is a usage error, not a fallback.
#[test]
fn variant_auto_follows_tridist_isa() {
    let a = tetrahedron("variant-auto");
    let a = a.as_str();
    // the first line of `tridist mesh` names the instruction set it runs
    let runs = |isa: Option<&str>| {
        let (code, out, err) = tridist_isa(&["mesh", a, a, "--pose-b", "3,0,0"], "", isa);
        assert_eq!(code, 0, "TRIDIST_ISA={isa:?}: {err}");
        assert!(out.contains("distance: 2 "), "{out}");
        out.lines().next().unwrap().rsplit(' ').nth(1).unwrap().to_string()
    };
    let best = tridist::Isa::best();
    assert_eq!(runs(None), best.name());
    assert_eq!(runs(Some("")), best.name());
    for isa in tridist::Isa::ALL.into_iter().filter(|i| i.is_available()) {
        assert_eq!(runs(Some(isa.name())), isa.name());
        // eval alike: the same answers as --variant named
        let pair = "p 0 0 0 1 0 0 0 1 0 0.25 0.25 2 3 0.25 5 0.25 3 5\n";
        let (code, auto, err) = tridist_isa(&["eval"], pair, Some(isa.name()));
        assert_eq!(code, 0, "{err}");
        let named = tridist_scenes::eval::Variant::from_isa(isa).name();
        let (_, named, _) = tridist(&["eval", "--variant", named], pair);
        assert_eq!((auto.as_str(), named.as_str()), ("p 4.0\n", "p 4.0\n"));
    }
    for bad in ["avx1024", "AVX2FMA"] {
        let (code, out, err) = tridist_isa(&["mesh", a, a], "", Some(bad));
        assert_eq!(code, 2, "TRIDIST_ISA={bad}: {out}{err}");
        assert!(out.is_empty() && err.contains("TRIDIST_ISA") && err.contains("unknown variant"), "{err}");
    }
    // a variant this CPU lacks, where there is one
    if let Some(lacking) = tridist::Isa::ALL.into_iter().find(|i| !i.is_available()) {
        let (code, _, err) = tridist_isa(&["eval"], "", Some(lacking.name()));
        assert_eq!(code, 2, "{err}");
        assert!(err.contains("not available") || err.contains("not compiled"), "{err}");
    }
}

/// Meshes so far apart that their squared distance overflows: the squared distance is the
/// documented `+inf`, but the distances printed are the closest points' (they printed `inf`),
/// and huge numbers print in exponent form (the margin printed 301 digits).
#[test]
fn mesh_distances_whose_squares_overflow() {
    let a = tetrahedron("overflow");
    let a = a.as_str();
    let close = |x: f64, want: f64, what: &str, out: &str| {
        assert!((x - want).abs() <= 1e-15 * want, "{what}: {x:e}, want {want:e}: {out}");
    };
    // the copy 1e200 along x: its vertex (1e200, 0, 0) against the first's (1, 0, 0)
    let (code, out, err) =
        tridist(&["mesh", a, a, "--pose-b", "1e200,0,0", "--point", "-1e200,0,0", "--margin", "1e300"], "");
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("(squared overflows f64)"), "{out}");
    close(number_after(&out, "distance: "), 1e200, "distance", &out);
    // (-1e200, 0, 0) against the copy's vertex (1e200, 0, 0)
    close(number_after(&out, "closest point of the second mesh: 1e200 0 0 at "), 2e200, "point", &out);
    // every pair of the 4 x 4 is within 1e300, the nearest first
    assert!(out.contains("contacts within 1e300: 16 "), "{out}");
    let c = contact_lines(&out);
    assert_eq!(c.len(), 10, "{out}");
    close(c[0].1, 1e200, "nearest contact", &out);
    assert!(c.iter().all(|k| k.1.is_finite() && k.1 >= c[0].1), "{out}");
    // f32: the copy 1e30 along x (the square, 1e60, is beyond f32)
    let (code, out, err) = tridist(&["mesh", a, a, "--pose-b", "1e30,0,0", "--precision", "f32"], "");
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("(squared overflows f32)"), "{out}");
    close(number_after(&out, "distance: "), f64::from(1e30f32) - 1.0, "f32 distance", &out);
    // a margin beyond f32's range: said so (it was "margin must be finite and non-negative")
    let (code, _, err) = tridist(&["mesh", a, a, "--margin", "1e300", "--precision", "f32"], "");
    assert_eq!(code, 3, "{err}");
    assert!(err.contains("--margin 1e300 is beyond the range of f32"), "{err}");
}

/// Poses files end to end: `tridist poses` writes each protocol's poses (parsed back here as
/// rigid 12-number poses), `tridist mesh --normalise --poses` answers them line by line (the
/// trajectory's two ends apart, its middle through the fixed mesh), the three line forms and
/// labels are read, malformed files and conflicting flags are refused with their reason.
#[test]
fn poses_files_are_written_and_timed() {
    let a = tetrahedron("poses");
    let dir = tmp("poses");
    for (protocol, count) in [("ball", 4), ("trajectory", 3), ("near", 2)] {
        let (code, out, err) =
            tridist(&["poses", &a, &a, "--protocol", protocol, "--count", &count.to_string()], "");
        assert_eq!(code, 0, "{err}");
        let lines: Vec<Vec<&str>> =
            out.lines().filter(|l| !l.starts_with('#')).map(|l| l.split(' ').collect()).collect();
        assert_eq!(lines.len(), count, "{out}");
        for (k, l) in lines.iter().enumerate() {
            assert_eq!(l[0], format!("{protocol}-{k}"));
            let v: Vec<f64> = l[1..].iter().map(|x| x.parse().unwrap()).collect();
            assert_eq!(v.len(), 12, "{l:?}");
            // a rotation: unit rows
            for r in v[3..].chunks(3) {
                assert!((r.iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-12, "{l:?}");
            }
        }
        let file = dir.join(format!("{protocol}.txt"));
        std::fs::write(&file, &out).unwrap();
        let (code, got, err) = tridist(
            &["mesh", &a, &a, "--normalise", "--poses", file.to_str().unwrap(), "--budget-ms", "1"],
            "",
        );
        assert_eq!(code, 0, "{err}");
        let rows: Vec<Vec<&str>> = got
            .lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with("meshes:"))
            .map(|l| l.split(' ').collect())
            .collect();
        assert_eq!(rows.len(), count, "{got}");
        for (k, r) in rows.iter().enumerate() {
            assert_eq!((r[0], r.len()), (format!("{protocol}-{k}").as_str(), 7), "{got}");
            let (d, hit): (f64, &str) = (r[1].parse().unwrap(), r[5]);
            assert!(r[4].parse::<f64>().unwrap() > 0.0 && r[6].parse::<f64>().unwrap() >= 0.0, "{r:?}");
            assert_eq!(hit == "yes", d == 0.0, "{r:?}");
            match protocol {
                "trajectory" => assert_eq!(hit == "yes", k == 1, "{r:?}"),
                // the gap, 1e-3 of the normalised size, bisected from above
                "near" => assert!((1e-3..1.001e-3).contains(&d), "{r:?}"),
                _ => {}
            }
        }
    }
    // the three forms, labelled or not, and the contacts columns
    let file = dir.join("forms.txt");
    std::fs::write(&file, "# comment\n\n3 0 0\nturned 3 0 0 0 0 1 90\n3 0 0 1 0 0 0 1 0 0 0 1\n").unwrap();
    let (code, got, err) =
        tridist(&["mesh", &a, &a, "--poses", file.to_str().unwrap(), "--margin", "2.5"], "");
    assert_eq!(code, 0, "{err}");
    // the contacts on two threads are the same (their times differ)
    let (code, two, err) = tridist(
        &["mesh", &a, &a, "--poses", file.to_str().unwrap(), "--margin", "2.5", "--threads", "2"],
        "",
    );
    assert_eq!(code, 0, "{err}");
    let counts =
        |t: &str| t.lines().skip(2).map(|l| l.split(' ').nth(7).map(String::from)).collect::<Vec<_>>();
    assert_eq!(counts(&got), counts(&two), "{got}\n{two}");
    let (code, _, err) = tridist(&["mesh", &a, &a, "--threads", "0"], "");
    assert_eq!(code, 2, "{err}");
    let rows: Vec<&str> = got.lines().filter(|l| !l.starts_with("meshes:")).collect();
    assert!(rows[0].ends_with("contacts_within_2.5 contacts_ms"), "{got}");
    let labels: Vec<&str> = rows[1..].iter().map(|r| r.split(' ').next().unwrap()).collect();
    assert_eq!(labels, ["pose-0", "turned", "pose-2"]);
    for r in [rows[1], rows[3]] {
        let c: Vec<&str> = r.split(' ').collect();
        // two unit tetrahedra 2 apart: 12 contacts within 2.5 (as the README's example)
        assert_eq!((c[1], c[5], c[7]), ("2", "no", "12"), "{r}");
    }
    // refused: a malformed line (with its number), no pose, a flag that names another pose
    for (text, says) in [
        ("1 2 3\n1 2\n", "line 2: a pose is 3, 7 or 12 numbers"),
        ("x 1 2 nan\n", "line 1: a non-finite number"),
        ("0 0 0 0 0 0 90\n", "line 1: "),
        ("# nothing\n", "no pose in the file"),
    ] {
        std::fs::write(&file, text).unwrap();
        let (code, out, err) = tridist(&["mesh", &a, &a, "--poses", file.to_str().unwrap()], "");
        assert_eq!(code, 3, "{text}: {out}");
        assert!(err.contains(says), "{text}: {err}");
    }
    let (code, _, err) =
        tridist(&["mesh", &a, &a, "--poses", file.to_str().unwrap(), "--pose-b", "1,0,0"], "");
    assert_eq!(code, 2, "{err}");
    let (code, _, err) = tridist(&["poses", &a, &a, "--protocol", "spiral"], "");
    assert_eq!(code, 2, "{err}");
}

/// One table of the protocol sections of MESH.md (`n` placements): tridist in both precisions
/// and a row per C++ mesh peer, measured exactly when that peer was built, its distances
/// agreeing with tridist f64's (float within float's rounding of a [-1, 1]^3 scene).
fn peer_table(table: &str, n: usize) {
    use tridist_scenes::mesh_peer::MeshLib;
    let rows: Vec<Vec<&str>> = table
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| library"))
        .map(|l| l.split(" | ").map(|c| c.trim_matches(['|', ' '])).collect())
        .collect();
    assert_eq!(rows.len(), 2 + MeshLib::ALL.len() + 1, "{table}");
    let num = |x: &str| x.trim_end_matches('x').parse::<f64>().unwrap_or_else(|_| panic!("{x:?} in {table}"));
    for r in &rows[..2] {
        assert!(r[0].starts_with("tridist f") && num(r[1]) > 0.0 && num(r[2]) > 0.0, "{r:?}");
    }
    let libs = MeshLib::ALL;
    for (r, lib) in rows[2..].iter().zip(libs.iter().chain([&libs[2]])) {
        assert!(r[0].starts_with(lib.name()), "{r:?} {lib:?}");
        assert_eq!(!r[1].starts_with("not built"), lib.available(), "{r:?}");
        if lib.available() {
            let wrong: usize =
                r[8].strip_suffix(&format!(" of {n}")).unwrap_or_else(|| panic!("{r:?}")).parse().unwrap();
            // the established peers agree everywhere (a pose passed transposed or a wrong
            // distance of ours would show here); TrueForm's axis-aligned trees do not
            if matches!(lib, MeshLib::Fcl | MeshLib::Coal | MeshLib::TrueFormObbrssF64) {
                assert_eq!(wrong, 0, "{r:?}: distances disagree");
            }
            if wrong < n {
                assert!(num(r[1]) > 0.0 && num(r[3]) > 0.0 && num(r[4]) <= num(r[3]), "{r:?}");
            }
            assert_eq!(r[5], format!("{} of {}", r[5].split(' ').next().unwrap(), n - wrong), "{r:?}");
            let tol = if r[0].contains("float") { 1e-5 } else { 1e-9 };
            assert!(num(r[9]) <= tol, "{r:?}: distances disagree");
        }
    }
}
