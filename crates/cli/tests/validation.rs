//! The DEM validation scenarios of examples/dem run and pass their checks.
//! The settling column takes minutes: `cargo test --release -- --ignored`.

use std::process::Command;

fn run_example(name: &str) -> serde_json::Value {
    let dir = tempfile::tempdir().unwrap();
    let file = format!(
        "{}/../../examples/dem/{name}.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let o = Command::new(env!("CARGO_BIN_EXE_grains"))
        .args(["run", &file, "--out", dir.path().to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{name} failed: {err}");
    for f in [
        "scenario.toml",
        "history.csv",
        "summary.json",
        "frames/series.pvd",
        "plots/energies.png",
    ] {
        assert!(dir.path().join(f).exists(), "{name}: missing {f}");
    }
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("summary.json")).unwrap())
            .unwrap();
    for c in s["checks"].as_array().unwrap() {
        assert_eq!(c["pass"], true, "{name}: {c}");
    }
    s
}

#[test]
fn head_on() {
    let s = run_example("head_on");
    assert_eq!(s["checks"].as_array().unwrap().len(), 10);
}

#[test]
fn oblique_impact() {
    let s = run_example("oblique_impact");
    assert_eq!(s["checks"].as_array().unwrap().len(), 2);
}

#[test]
#[ignore = "minutes in a debug build; run with --release -- --ignored"]
fn settling_column() {
    let s = run_example("settling_column");
    assert_eq!(s["status"], "at_rest");
}
