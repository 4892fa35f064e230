//! Replays the committed regression cases (`tests/regressions/*.txt`: one labelled case per
//! line, `#` comments) on every variant and precision against the oracle and the bound table.
//! Held to the loosest row over the families (adversarial input). Cases found by tests and fuzzing are added
//! here with a comment naming the root cause.

use tridist::Query;
use tridist_scenes::bounds::violations;
use tridist_scenes::eval::{parse_case_line_exact, truth};
use tridist_scenes::Float;

fn replay<T: Float>(file: &str, text: &str) -> usize {
    let mut n = 0;
    for (ln, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let (case, exact) =
            parse_case_line_exact::<T>(line).unwrap_or_else(|e| panic!("{file}:{}: {e}", ln + 1));
        // The recorded exact answer of the labelled query (f64: the decimals' own reading).
        if let (Some(exact), "f64") = (exact, T::NAME) {
            let q = case.label.split('/').next().and_then(Query::parse).expect("label starts with its query");
            let t = truth(q, std::slice::from_ref(&case));
            assert_eq!(t[0].d2, exact, "{file}:{}: the oracle's answer changed", ln + 1);
        }
        let cases = vec![case];
        for &q in Query::ALL {
            let bad = violations(q, None, &cases, &truth(q, &cases));
            assert!(bad.is_empty(), "{file}:{}:\n{}", ln + 1, bad.join("\n"));
        }
        n += 1;
    }
    n
}

#[test]
fn replay_regressions() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/regressions");
    let mut total = 0;
    for entry in std::fs::read_dir(&dir).expect("tests/regressions exists") {
        let path = entry.expect("readable").path();
        if path.extension().is_some_and(|e| e == "txt") {
            let text = std::fs::read_to_string(&path).expect("readable");
            let name = path.display().to_string();
            total += replay::<f64>(&name, &text);
            // f32: the same decimals rounded to f32 (a different but equally valid case).
            replay::<f32>(&name, &text);
        }
    }
    assert!(total > 0, "no regression case found in {}", dir.display());
}
