//! `TRIDIST_ISA` as a user sets it. The variable is read once per process, so each value is
//! tried in a child process: this test binary run again on this one test, with the variable
//! set and the expected outcome passed beside it (no test changes its own environment).

use std::process::Command;
use tridist::{Engine, Error, Isa, ISA_ENV};

/// Set in the child: what `TRIDIST_ISA` must give (a variant's name, `unknown` or
/// `unavailable`).
const EXPECT: &str = "TRIDIST_ISA_TEST_EXPECT";

#[test]
fn tridist_isa_picks_the_variant_and_auto_falls_back() {
    if let Ok(want) = std::env::var(EXPECT) {
        let (got, auto) = (Engine::from_env(), Engine::auto().isa());
        match want.as_str() {
            "unknown" => assert!(matches!(got, Err(Error::UnknownIsa(_))), "{got:?}"),
            "unavailable" => assert!(matches!(got, Err(Error::Unavailable(_))), "{got:?}"),
            name => {
                let isa = Isa::parse(name).expect("a variant's name");
                assert_eq!(got.map(|e| e.isa()), Ok(isa));
                assert_eq!(auto, isa, "Engine::auto follows TRIDIST_ISA");
                return;
            }
        }
        assert_eq!(auto, Isa::best(), "Engine::auto falls back to the best variant");
        return;
    }
    // unset and empty: the best variant; every variant by name, available or not; a typo
    let mut cases =
        vec![(None, Isa::best().name()), (Some(""), Isa::best().name()), (Some("avx1024"), "unknown")];
    for isa in Isa::ALL {
        let want = if Engine::new(isa).is_ok() { isa.name() } else { "unavailable" };
        cases.push((Some(isa.name()), want));
    }
    for (value, want) in cases {
        let mut child = Command::new(std::env::current_exe().unwrap());
        child.args(["--exact", "tridist_isa_picks_the_variant_and_auto_falls_back", "--test-threads", "1"]);
        match value {
            Some(v) => child.env(ISA_ENV, v),
            None => child.env_remove(ISA_ENV),
        };
        let out = child.env(EXPECT, want).output().unwrap();
        let text =
            format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
        assert!(out.status.success(), "TRIDIST_ISA={value:?}, expected {want}:\n{text}");
        // the child ran the test (the filter matched it)
        assert!(text.contains("1 passed"), "TRIDIST_ISA={value:?}:\n{text}");
    }
}
