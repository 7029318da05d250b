//! The 3D DEM examples (examples/dem3d) run and pass their checks, and their outputs
//! follow the run contract: history with 3D wall loads, frames of 3D points, the side
//! and top views.

mod common;
use common::*;

/// Runs `examples/dem3d/NAME.toml`, which passes its checks: its summary and its
/// history's header.
fn run_dem3d_example(name: &str, checks: usize) -> (serde_json::Value, String) {
    let (code, s, header) = run_dem3d(name, checks);
    assert_eq!(code, 0, "{name} failed: {s}");
    (s, header)
}

/// Runs `examples/dem3d/NAME.toml` and checks its outputs: its exit code (0, or 2 with a
/// failed check), summary and history's header.
fn run_dem3d(name: &str, checks: usize) -> (i32, serde_json::Value, String) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = grains(&[
        "run",
        example(&format!("dem3d/{name}.toml")).to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let all = s["checks"].as_array().unwrap();
    assert_eq!(all.len(), checks, "{name}");
    let failed = all.iter().any(|c| c["pass"] != true);
    assert_eq!(o.code, if failed { 2 } else { 0 }, "{name}: {}", o.stderr);
    for f in [
        "plots/particles_side.png",
        "plots/particles_top.png",
        "plots/energies.png",
        "frames/series.pvd",
    ] {
        assert!(out.join(f).is_file(), "{name}: no {f}");
    }
    let bytes = std::fs::read(out.join("frames/particles_00000.vtp")).unwrap();
    let frame = String::from_utf8_lossy(&bytes);
    assert!(
        frame.contains("Name=\"omega\" NumberOfComponents=\"3\""),
        "{name}"
    );
    assert!(
        frame.contains("Name=\"stress\" NumberOfComponents=\"9\""),
        "{name}"
    );
    let history = std::fs::read_to_string(out.join("history.csv")).unwrap();
    (o.code, s, history.lines().next().unwrap_or("").to_string())
}

#[test]
fn chung_ooi_test1() {
    run_dem3d_example("chung_ooi_test1", 4);
}

#[test]
fn chung_ooi_test2() {
    run_dem3d_example("chung_ooi_test2", 3);
}

#[test]
fn chung_ooi_test3() {
    run_dem3d_example("chung_ooi_test3", 4);
}

#[test]
fn chung_ooi_test4() {
    run_dem3d_example("chung_ooi_test4", 6);
}

#[test]
fn chung_ooi_test5() {
    run_dem3d_example("chung_ooi_test5", 6);
}

#[test]
fn settling_column() {
    let (s, header) = run_dem3d_example("settling_column", 2);
    assert_eq!(s["status"], "at_rest");
    // The energy ledger, on by default: its columns, figures and closure check.
    for c in [
        "contact_stored",
        "dissipated_damping",
        "wall_work",
        "ledger_residual",
    ] {
        assert!(header.split(',').any(|h| h == c), "no {c} in {header}");
    }
    let closure = s["figures"]["energy_ledger"]["closure"].as_f64().unwrap();
    assert!(closure < 0.01, "{closure}");
}

/// A sphere on a translating rectangle (the belt's surface velocity in the contact)
/// ends rolling at 2/7 of the belt's speed.
#[test]
fn belt() {
    run_dem3d_example("belt", 1);
}

/// The turning drum: its surface angle in range, its torque about the axis recorded
/// and balancing the weight's moment.
#[test]
fn drum_small() {
    let (_, header) = run_dem3d_example("drum_small", 2);
    assert!(header.contains("drum_torque_axis"), "{header}");
}

/// The recycling silo drains through its floor's hole at a rate within Beverloo's
/// spread.
#[test]
fn silo_small() {
    let (s, _) = run_dem3d_example("silo_small", 1);
    assert!(s["figures"]["mass_flow_rate_rate_kg_s"].as_f64().unwrap() > 0.0);
}

/// Spheres poured into a box: every one poured is in the box, and the floor carries
/// their weight once they settle.
#[test]
fn pour_small() {
    let (s, _) = run_dem3d_example("pour_small", 2);
    assert_eq!(s["poured"], 300, "{s}");
}

/// The small column collapses once its tube is released: the tube carries no load at
/// the end, and the run-out matches Lube et al.'s within the example's tolerance. The
/// edge of the continuous deposit, a figure beside the check, lies within the grains
/// and short of the 99 % radius (VALIDATION.md, "Column collapse").
#[test]
fn collapse_small() {
    let (s, header) = run_dem3d_example("collapse_small", 1);
    assert!(header.contains("tube_fx"), "{header}");
    let f = &s["figures"];
    let g = |k: &str| f[format!("runout_over_lube_{k}")].as_f64().unwrap();
    let a = g("aspect_ratio");
    assert!(a > 1.0 && a < 1.7, "{s}");
    let (r0, r, edge, front) = (g("r0_m"), g("r_inf_m"), g("edge_m"), g("front_m"));
    assert!(r > 2.0 * r0, "{s}");
    assert!(r0 < edge && edge < r && r <= front, "{s}");
    assert_eq!(g("edge_coverage"), 0.5, "{s}");
    assert_eq!(g("runout_edge"), (edge - r0) / r0, "{s}");
}

#[test]
fn check_reports_a_3d_scenario() {
    let o = grains(&[
        "check",
        example("dem3d/settling_column.toml").to_str().unwrap(),
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    for what in ["3 (spheres)", "granular", "memory", "wall time"] {
        assert!(o.stdout.contains(what), "{what} not in {}", o.stdout);
    }
}
