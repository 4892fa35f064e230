//! What the CLI tests share: running the `tridist` binary as a user does.

use std::io::Write;
use std::process::{Command, Stdio};

/// Runs `tridist args` with `stdin`; returns (exit status, stdout, stderr).
pub fn tridist(args: &[&str], stdin: &str) -> (i32, String, String) {
    tridist_env(args, stdin, None)
}

/// [`tridist`] with `TRIDIST_ISA` set to `isa` (`None`: removed).
#[allow(dead_code)] // (each test binary compiles this module; not all use this)
pub fn tridist_isa(args: &[&str], stdin: &str, isa: Option<&str>) -> (i32, String, String) {
    tridist_env(args, stdin, Some(isa))
}

/// [`tridist`], `TRIDIST_ISA` inherited (`None`) or set (`Some(Some(v))`) or removed.
fn tridist_env(args: &[&str], stdin: &str, isa: Option<Option<&str>>) -> (i32, String, String) {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_tridist"));
    match isa {
        Some(Some(v)) => cmd.env(tridist::ISA_ENV, v),
        Some(None) => cmd.env_remove(tridist::ISA_ENV),
        None => &mut cmd,
    };
    let mut child = cmd
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    // A run that rejects its arguments exits without reading its input: a closed pipe then.
    match child.stdin.take().expect("stdin").write_all(stdin.as_bytes()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => {}
        r => r.expect("write"),
    }
    let out = child.wait_with_output().expect("wait");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

/// A fresh directory for test files, per process and `name`.
#[allow(dead_code)] // (each test binary compiles this module; not all use this)
pub fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("tridist-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The tetrahedron of the corner (0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1) as an OFF file in
/// [`tmp`]`(name)`; its path.
#[allow(dead_code)] // (each test binary compiles this module; not all use this)
pub fn tetrahedron(name: &str) -> String {
    let a = tmp(name).join("a.off");
    let tet = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n3 0 2 3\n3 1 2 3\n";
    std::fs::write(&a, tet).unwrap();
    a.to_str().unwrap().to_string()
}

/// The number after `prefix` on the line that starts with it.
#[allow(dead_code)] // (each test binary compiles this module; not all use this)
pub fn number_after(out: &str, prefix: &str) -> f64 {
    out.lines()
        .find_map(|l| l.strip_prefix(prefix))
        .and_then(|l| l.split_whitespace().next())
        .unwrap_or_else(|| panic!("no line {prefix:?} in {out}"))
        .parse()
        .unwrap_or_else(|e| panic!("{prefix:?}: {e} in {out}"))
}
