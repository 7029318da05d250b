//! What every test of the `grains` binary needs: run it, write a scenario and run that,
//! read a summary, and assert that bad input is refused the way users are promised
//! (exit 1, one error line naming the key and the value, nothing written).
// Each test binary uses its own subset of these.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// A small DEM scenario that runs: one disk resting 0.1 mm above a floor, for 0.1 µs;
/// the bad-input tests edit it.
pub const ONE_DISK: &str = r#"
name = "bad"
gravity = [0.0, -9.81]

[domain]
lo = [0.0, 0.0]
hi = [0.01, 0.01]

[[material]]
name = "quartz"
density = 2560.0
youngs = 72.0e9
poisson = 0.27
restitution = 0.5
friction = 0.3

[[particles]]
source = "list"
material = "quartz"
disks = [{ at = [0.005, 0.0006], radius = 0.0005 }]

[[wall]]
name = "floor"
shape = "segment"
a = [0.0, 0.0]
b = [0.01, 0.0]

[run]
duration = 1.0e-7
"#;

/// What a command printed and how it ended.
pub struct Out {
    /// Exit code (-1 when killed by a signal).
    pub code: i32,
    /// Standard output.
    pub stdout: String,
    /// Standard error.
    pub stderr: String,
}

/// Runs `grains ARGS` in `dir` (the test's own directory when `None`).
pub fn grains_in(dir: Option<&Path>, args: &[&str]) -> Out {
    let mut c = Command::new(env!("CARGO_BIN_EXE_grains"));
    if let Some(d) = dir {
        c.current_dir(d);
    }
    let o = c.args(args).output().expect("run grains");
    Out {
        code: o.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&o.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&o.stderr).into_owned(),
    }
}

/// Runs `grains ARGS`.
pub fn grains(args: &[&str]) -> Out {
    grains_in(None, args)
}

/// Writes `text` as `s.toml` (and `extra` files beside it) in a fresh directory and runs
/// `grains run s.toml --out out` there, with `args` added.
pub fn run_text(text: &str, extra: &[(&str, &str)], args: &[&str]) -> (Out, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), text).unwrap();
    for (name, body) in extra {
        std::fs::write(dir.path().join(name), body).unwrap();
    }
    let mut all = vec!["run", "s.toml", "--out", "out"];
    all.extend_from_slice(args);
    let out = grains_in(Some(dir.path()), &all);
    (out, dir)
}

/// The summary a run wrote into `dir/out`.
pub fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("out/summary.json")).unwrap()).unwrap()
}

/// An example scenario's path, from the workspace root.
pub fn example(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(rel)
}

/// Asserts that a run was refused as bad input: exit 1, exactly one error line, which
/// contains every string of `must_contain`, and no output directory in `dir`.
pub fn assert_refused(out: &Out, dir: &Path, must_contain: &[&str]) {
    assert_eq!(out.code, 1, "exit code; stderr: {}", out.stderr);
    assert!(!dir.join("out").exists(), "an output directory was written");
    let errors: Vec<&str> = out.stderr.lines().filter(|l| l.contains("error")).collect();
    assert_eq!(errors.len(), 1, "{}", out.stderr);
    for s in must_contain {
        assert!(
            errors[0].contains(s),
            "error line {:?} lacks {s:?}",
            errors[0]
        );
    }
}

/// Runs `text` and asserts that it is refused (see [`assert_refused`]).
pub fn refused(text: &str, must_contain: &[&str]) {
    let (out, dir) = run_text(text, &[], &[]);
    assert_refused(&out, dir.path(), must_contain);
}

/// Runs an example (path under `examples/`) into a scratch directory: its outcome and
/// its summary.
pub fn run_example(rel: &str) -> (Out, serde_json::Value) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = grains(&[
        "run",
        example(rel).to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let s = std::fs::read_to_string(out.join("summary.json"))
        .map(|t| serde_json::from_str(&t).unwrap())
        .unwrap_or(serde_json::Value::Null);
    (o, s)
}

/// For each (from, to, must_contain): `base` with `from` replaced by `to` is refused
/// (see [`assert_refused`]).
pub fn refused_all(base: &str, cases: &[(&str, &str, &[&str])]) {
    for (from, to, must) in cases {
        assert!(base.contains(from), "the base lacks {from:?}");
        refused(&base.replace(from, to), must);
    }
}

/// `grains check --json` of scenario `text`, which must pass: its figures.
pub fn check_json(text: &str) -> serde_json::Value {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("s.toml");
    std::fs::write(&file, text).unwrap();
    let o = grains(&["check", file.to_str().unwrap(), "--json"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    serde_json::from_str(&o.stdout).unwrap()
}
