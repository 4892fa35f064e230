//! Stable replay of the fuzz targets: every committed finding in `fuzz/regressions/<target>/`
//! (raw libFuzzer inputs, decoded exactly as the fuzzer decodes them: the bodies are shared in
//! `tridist_scenes::fuzzing`) and a seed corpus from the family generators, through the same
//! target bodies the fuzzer runs. A failure names the input file.

use std::path::{Path, PathBuf};

use tridist_scenes::fuzzing::{seed_inputs, Judge, Target, TARGETS};

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
const REPLAYED_AT_LEAST: usize = 25;

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
