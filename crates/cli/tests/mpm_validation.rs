//! The bardenhagen-1998 MPM cases through the `grains` binary, as the user runs them.
//! `#[ignore]`d (run with `cargo test --release -p grains --test mpm_validation --
//! --ignored`): together they take about three minutes in a release build. Each
//! example must exit 0 with every check passing; the figures the checks do not bound are
//! held to what VALIDATION.md reports.

mod common;
use common::*;

/// Runs an example (under `examples/`): every check passes and it exits 0; its summary.
fn passes(example: &str) -> serde_json::Value {
    let (o, s) = run_example(example);
    assert_eq!(o.code, 0, "{example}: exit {}: {}", o.code, o.stderr);
    let checks = s["checks"].as_array().unwrap();
    assert!(!checks.is_empty(), "{example}: no checks");
    for c in checks {
        assert!(c["pass"] == true, "{example}: {c}");
    }
    s
}

/// The normal restitution of impact `k` (from 1) of the cylinder.
fn restitution(s: &serde_json::Value, k: usize) -> f64 {
    s["figures"]["cylinder_impacts"][k - 1]["normal_restitution"]
        .as_f64()
        .unwrap()
}

#[test]
#[ignore]
fn cylinder_bounce_frictionless() {
    let s = passes("bardenhagen1998/cylinder_bounce_frictionless.toml");
    // The elastic cylinder keeps part of each impact as vibration (VALIDATION.md).
    let e = restitution(&s, 1);
    assert!((0.97..0.99).contains(&e), "{e}");
}

#[test]
#[ignore]
fn cylinder_bounce_friction() {
    passes("bardenhagen1998/cylinder_bounce_friction.toml");
}

#[test]
#[ignore]
fn cylinder_bounce_frictionless_fine() {
    passes("bardenhagen1998/cylinder_bounce_frictionless_fine.toml");
}

#[test]
#[ignore]
fn cylinder_bounce_48() {
    let s = passes("bardenhagen1998/cylinder_bounce_48.toml");
    let e = restitution(&s, 1);
    assert!((0.970..0.977).contains(&e), "{e}");
}

#[test]
#[ignore]
fn block_on_incline() {
    passes("bardenhagen1998/block_on_incline.toml");
}

#[test]
#[ignore]
fn cylinder_on_incline() {
    passes("bardenhagen1998/cylinder_on_incline.toml");
}

#[test]
#[ignore]
fn concentric_cylinders_bonded() {
    passes("bardenhagen1998/concentric_cylinders_bonded.toml");
}

#[test]
#[ignore]
fn concentric_cylinders_debond() {
    let s = passes("bardenhagen1998/concentric_cylinders_debond.toml");
    // The lattice's eightfold registry (the paper saw 4, once 2).
    assert_eq!(s["figures"]["initiation_sites"], 8);
}

/// The small sheared cells (issue 13): every check passes; pairwise contact keeps the
/// free bodies' exchanges to round-off; the dry cell's grains roll and collide (the
/// boundaries carry load) and the binder debonds.
#[test]
#[ignore]
fn shear_cells_small() {
    for e in [
        "bardenhagen1998/shear_cell_dry_small.toml",
        "bardenhagen1998/shear_cell_binder_small.toml",
        "bardenhagen1998/pbx9501_small.toml",
    ] {
        let s = passes(e);
        let f = &s["figures"];
        let imbalance = f["contact_imbalance"].as_f64().unwrap();
        let impulse = f["boundary_impulse"].as_f64().unwrap();
        assert!(impulse > 0.0 && imbalance <= 1e-12 * impulse, "{e}: {f}");
        assert!(f["shear_stress_max"].as_f64().unwrap() > 0.0, "{e}: {f}");
        if !e.contains("dry") {
            assert!(
                f["debonded_length_final"].as_f64().unwrap() > 0.0,
                "{e}: {f}"
            );
        }
    }
}
