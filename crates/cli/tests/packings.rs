//! Packings on demand: a ring that names a packing spec (`source = "spec"`) is sized by
//! `grains check` from the spec alone, made on the first `grains run`, reused after,
//! rebuilt when the spec changes or the cached file was edited or truncated, and
//! refused when the spec packs another annulus.

mod common;
use common::*;
use std::path::Path;

const RING: &str = include_str!("../../sim/tests/data/ring_tiny.toml");

/// The tiny ring's annulus, packed at 0.1 mm: about a thousand disks in seconds. Grown
/// to its target fraction, so that its sizes are known beforehand.
const SPEC: &str = r#"
name = "tiny"
seed = 3
[domain]
shape = "annulus"
r_in = 0.002
r_out = 0.0028
[sizes]
distribution = "gaussian"
d0 = 0.1e-3
delta = 0.113
[protocol]
rate = 1e-3
finish = "target"
target_fraction = 0.8
"#;

fn scenario() -> String {
    RING.replace(
        "source = \"lattice\"\nd0 = 0.1e-3",
        "source = \"spec\"\nspec = \"spec.toml\"",
    )
    .replace("duration = 3.0e-6", "duration = 0.4e-6")
    .replace("snapshots = [2.0e-6]", "snapshots = [0.2e-6]")
}

fn cache_dirs(dir: &Path) -> Vec<String> {
    match std::fs::read_dir(dir.join("runs/packings")) {
        Ok(rd) => rd
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect(),
        Err(_) => Vec::new(),
    }
}

fn check_in(dir: &Path) -> serde_json::Value {
    let o = grains_in(Some(dir), &["check", "s.toml", "--json"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    serde_json::from_str(&o.stdout).unwrap()
}

fn run_in(dir: &Path) -> Out {
    let o = grains_in(
        Some(dir),
        &["run", "s.toml", "--out", "out", "--threads", "1"],
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    o
}

#[test]
fn made_once_reused_and_sized_beforehand() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.toml"), scenario()).unwrap();
    std::fs::write(d.join("spec.toml"), SPEC).unwrap();

    // Sized from the spec, nothing made.
    let before = check_in(d);
    assert_eq!(before["packing_cached"], false);
    assert!(cache_dirs(d).is_empty(), "check made something");
    let n_est = before["particles"].as_f64().unwrap();
    let fb_est = before["fill_to_burster_ratio"].as_f64().unwrap();

    // The first run makes it, under the spec's name and key.
    let first = run_in(d);
    assert!(first.stderr.contains("making it"), "{}", first.stderr);
    let dirs = cache_dirs(d);
    assert_eq!(dirs.len(), 1);
    assert!(dirs[0].starts_with("tiny-"), "{dirs:?}");
    let s = summary(d);
    let n = s["particles"].as_f64().unwrap();
    let fb = s["figures"]["fill_to_burster_ratio"].as_f64().unwrap();
    assert!((n_est / n - 1.0).abs() < 0.02, "particles {n_est} vs {n}");
    assert!((fb_est / fb - 1.0).abs() < 0.02, "F/B {fb_est} vs {fb}");
    assert_eq!(check_in(d)["packing_cached"], true);

    // The second run reuses it.
    let second = run_in(d);
    assert!(!second.stderr.contains("making it"), "{}", second.stderr);

    // An edited or truncated file is caught by its key and made again.
    let file = d.join("runs/packings").join(&dirs[0]).join("packing.txt");
    let text = std::fs::read_to_string(&file).unwrap();
    let last = text.trim_end().rsplit('\n').next().unwrap().to_string();
    let edited = text.replacen(&last, &format!("1{last}"), 1);
    for broken in [edited, text[..text.len() / 2].to_string()] {
        std::fs::write(&file, broken).unwrap();
        let again = run_in(d);
        assert!(
            again.stderr.contains("edited or truncated") && again.stderr.contains("making it"),
            "{}",
            again.stderr
        );
        assert_eq!(
            std::fs::read_to_string(&file).unwrap(),
            text,
            "remade differently"
        );
    }

    // A changed spec gets a packing of its own.
    std::fs::write(d.join("spec.toml"), SPEC.replace("seed = 3", "seed = 4")).unwrap();
    assert_eq!(check_in(d)["packing_cached"], false);
    run_in(d);
    assert_eq!(cache_dirs(d).len(), 2);
}

#[test]
fn a_spec_for_another_annulus_is_refused() {
    let (out, dir) = run_text(
        &scenario(),
        &[(
            "spec.toml",
            &SPEC.replace("r_out = 0.0028", "r_out = 0.0030"),
        )],
        &[],
    );
    assert_refused(
        &out,
        dir.path(),
        &[
            "ring.packing.spec",
            "spec.toml",
            "r_out = 0.003 m",
            "r_out = 0.0028 m",
        ],
    );
    assert!(cache_dirs(dir.path()).is_empty());
    let o = grains_in(Some(dir.path()), &["check", "s.toml"]);
    assert_eq!(o.code, 1, "{}", o.stderr);
}

#[test]
fn a_missing_or_bad_spec_is_refused() {
    let (out, dir) = run_text(&scenario(), &[], &[]);
    assert_refused(&out, dir.path(), &["ring.packing.spec", "spec.toml"]);
    let (out, dir) = run_text(
        &scenario(),
        &[("spec.toml", &SPEC.replace("delta = 0.113", "delta = 0.9"))],
        &[],
    );
    assert_refused(
        &out,
        dir.path(),
        &["ring.packing.spec", "sizes.delta", "0.9"],
    );
}
