//! Chung & Ooi's (2011) tests 1–5 in 2D (examples/dem/chung_ooi_test*.toml) run under
//! the granular law and pass their checks.

mod common;
use common::*;

/// Runs `examples/dem/NAME.toml`, which must pass its `checks` checks.
fn run_2d(name: &str, checks: usize) {
    let (o, s) = run_example(&format!("dem/{name}.toml"));
    assert_eq!(o.code, 0, "{name} failed: {}", o.stderr);
    let all = s["checks"].as_array().unwrap();
    assert_eq!(all.len(), checks, "{name}");
    for c in all {
        assert_eq!(c["pass"], true, "{name}: {c}");
    }
}

#[test]
fn chung_ooi_test1_in_2d() {
    run_2d("chung_ooi_test1", 4);
}

#[test]
fn chung_ooi_test2_in_2d() {
    run_2d("chung_ooi_test2", 3);
}

#[test]
fn chung_ooi_test3_in_2d() {
    run_2d("chung_ooi_test3", 4);
}

#[test]
fn chung_ooi_test4_in_2d() {
    run_2d("chung_ooi_test4", 6);
}

#[test]
fn chung_ooi_test5_in_2d() {
    run_2d("chung_ooi_test5", 6);
}
