//! The DEM validation scenarios of examples/dem run and pass their checks.
//! The settling column takes minutes: `cargo test --release -- --ignored`.

mod common;
use common::*;

fn run_dem_example(name: &str) -> serde_json::Value {
    let (o, s) = run_example(&format!("dem/{name}.toml"));
    assert_eq!(o.code, 0, "{name} failed: {}", o.stderr);
    for c in s["checks"].as_array().unwrap() {
        assert_eq!(c["pass"], true, "{name}: {c}");
    }
    s
}

#[test]
fn head_on() {
    let s = run_dem_example("head_on");
    assert_eq!(s["checks"].as_array().unwrap().len(), 10);
}

#[test]
fn oblique_impact() {
    let s = run_dem_example("oblique_impact");
    assert_eq!(s["checks"].as_array().unwrap().len(), 2);
}

#[test]
#[ignore = "minutes in a debug build; run with --release -- --ignored"]
fn settling_column() {
    let s = run_dem_example("settling_column");
    assert_eq!(s["status"], "at_rest");
}
