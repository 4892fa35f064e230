//! Stable replay of the fuzz targets: every committed finding in `fuzz/regressions/<target>/`
//! (raw libFuzzer inputs, decoded exactly as the fuzzer decodes them: the bodies are shared in
//! `tridist_scenes::fuzzing`) and a seed corpus from the family generators, through the same
//! target bodies the fuzzer runs. A failure names the input file.

use std::path::{Path, PathBuf};

use tridist_scenes::fuzzing::{measure, seed_inputs, Judge, Target, DISTANCE_TARGETS, TARGETS};

fn regressions_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz/regressions")
}

/// Runs `inputs` through `target`, judging every variant (the fuzzer judges one per input,
/// picked from its hash: a finding replays on all); returns one line per failing input. (The bodies return
/// their violation instead of panicking, so no process-wide panic hook is touched while other
/// tests run.)
fn replay(target: &Target, inputs: &[(String, Vec<u8>)]) -> Vec<String> {
    let mut failed = Vec::new();
    for (name, data) in inputs {
        if let Err(msg) = (target.run)(data, Judge::All) {
            failed.push(format!("{} {name}: {msg}", target.name));
        }
    }
    failed
}

fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let Ok(rd) = std::fs::read_dir(dir) else { return Vec::new() };
    let mut v: Vec<(String, Vec<u8>)> = rd
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.is_file() && p.extension().is_none_or(|x| x != "md"))
        .map(|p| (p.display().to_string(), std::fs::read(&p).expect("readable regression file")))
        .collect();
    v.sort();
    v
}

/// The committed findings as of this writing: the replay must find at least these.
const REPLAYED_AT_LEAST: usize = 29;

#[test]
fn committed_findings_replay_clean() {
    let dir = regressions_dir();
    assert!(dir.is_dir(), "{} is part of the repository", dir.display());
    let mut failed = Vec::new();
    let mut n = 0;
    for t in &TARGETS {
        let inputs = files(&dir.join(t.name));
        n += inputs.len();
        failed.extend(replay(t, &inputs));
    }
    // a replay that found nothing to replay (a moved folder, a renamed target) must not pass
    assert!(n >= REPLAYED_AT_LEAST, "only {n} committed findings found under {}", dir.display());
    assert!(
        failed.is_empty(),
        "{} of {n} committed fuzz findings fail again:\n{}",
        failed.len(),
        failed.join("\n")
    );
    // every folder names a target
    for e in std::fs::read_dir(&dir).unwrap().filter_map(|e| e.ok()) {
        if e.path().is_dir() {
            let name = e.file_name().to_string_lossy().to_string();
            assert!(TARGETS.iter().any(|t| t.name == name), "fuzz/regressions/{name} is not a target");
        }
    }
}

#[test]
fn family_seed_corpus_passes_every_pair_target() {
    let inputs: Vec<(String, Vec<u8>)> = seed_inputs(2, &[0x40, 0x01])
        .into_iter()
        .enumerate()
        .map(|(i, v)| (format!("seed {i}"), v))
        .collect();
    assert!(!inputs.is_empty(), "the family generators gave no seed input");
    let mut failed = Vec::new();
    for t in TARGETS.iter().filter(|t| !matches!(t.name, "raw_bits" | "parsers")) {
        failed.extend(replay(t, &inputs));
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

#[test]
fn replay_reports_a_failing_input() {
    fn picky(data: &[u8], _: Judge) -> Result<(), String> {
        if data.first() == Some(&7) {
            Err("seven".into())
        } else {
            Ok(())
        }
    }
    let t = Target { name: "picky", run: picky };
    let inputs = vec![("ok".to_string(), vec![1]), ("bad".to_string(), vec![7])];
    assert_eq!(replay(&t, &inputs), vec!["picky bad: seven".to_string()]);
}

/// The adversarial rows (`bounds::ADVERSARIAL`) are what the committed findings of the distance
/// targets measure now: a row below its measurement would let adversarial input fail on every
/// replay, a row far above it (stale: more than a tenth plus 0.1 over) would hold fuzzed input
/// to a bound nothing reaches. On failure the lines to paste into `scenes/src/adversarial.in`
/// are printed.
#[test]
fn adversarial_rows_are_the_committed_findings_measured() {
    use std::collections::BTreeMap;
    let dir = regressions_dir();
    let mut worst: BTreeMap<(&'static str, &'static str), [f64; 2]> = BTreeMap::new();
    for (target, queries) in DISTANCE_TARGETS {
        for q in queries {
            for p in ["f32", "f64"] {
                worst.insert((q.name(), p), [0.0, 0.0]);
            }
        }
        for (_, data) in files(&dir.join(target)) {
            for (q, p, [e, pe]) in measure(target, &data) {
                let w = worst.get_mut(&(q.name(), p)).expect("a query of the target");
                *w = [w[0].max(e), w[1].max(pe)];
            }
        }
    }
    let lines: Vec<String> = worst
        .iter()
        .map(|((q, p), [e, pe])| format!("    (\"{q}\", \"{p}\", [{e:.3e}, {pe:.3e}]),"))
        .collect();
    println!("ADVERSARIAL rows (scenes/src/adversarial.in):\n{}", lines.join("\n"));
    let mut wrong = Vec::new();
    for ((q, p), measured) in &worst {
        let query = tridist::Query::ALL.iter().copied().find(|x| x.name() == *q).expect("a query");
        let recorded = tridist_scenes::bounds::adversarial(query, p);
        for (k, what) in ["E", "point error"].iter().enumerate() {
            let m = measured[k];
            match recorded {
                None => wrong.push(format!("{q} {p}: no row recorded")),
                Some(r) if m > r[k] * (1.0 + 1e-3) => {
                    wrong.push(format!("{q} {p}: {what} measured {m:.3e} over the recorded {:.3e}", r[k]))
                }
                Some(r) if r[k] > m * 1.1 + 0.1 => {
                    wrong.push(format!("{q} {p}: {what} recorded {:.3e}, stale: measured {m:.3e}", r[k]))
                }
                _ => {}
            }
        }
    }
    wrong.dedup();
    assert!(wrong.is_empty(), "{}\npaste the lines printed above", wrong.join("\n"));
}
