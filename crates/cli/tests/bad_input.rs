//! Every kind of bad input is refused with one line naming the key, the value and what
//! is allowed, exit code 1, and no output directory.

mod common;
use common::*;

const BASE: &str = r#"
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

#[test]
fn the_base_scenario_runs() {
    let (out, dir) = run_text(BASE, &[], &[]);
    assert_eq!(out.code, 0, "{}", out.stderr);
    assert!(dir.path().join("out").exists());
}

#[test]
fn unknown_key() {
    refused(
        &BASE.replace("friction = 0.3", "friction = 0.3\nfrcition = 0.3"),
        &["frcition", "expected"],
    );
}

#[test]
fn zero_density() {
    refused(
        &BASE.replace("density = 2560.0", "density = 0.0"),
        &["material.quartz.density", "0", "> 0"],
    );
}

#[test]
fn negative_modulus() {
    refused(
        &BASE.replace("youngs = 72.0e9", "youngs = -1.0"),
        &["material.quartz.youngs", "-1", "> 0"],
    );
}

#[test]
fn zero_radius() {
    refused(
        &BASE.replace("radius = 0.0005", "radius = 0.0"),
        &["radius", "0", "> 0"],
    );
}

#[test]
fn negative_time_step() {
    refused(
        &BASE.replace("duration = 1.0e-7", "duration = 1.0e-7\ndt = -1.0e-9"),
        &["run.dt", "-1e-9", "> 0"],
    );
}

#[test]
fn restitution_out_of_range() {
    refused(
        &BASE.replace("restitution = 0.5", "restitution = 0.0"),
        &["material.quartz.restitution", "0", "(0, 1]"],
    );
    refused(
        &BASE.replace("restitution = 0.5", "restitution = 1.5"),
        &["material.quartz.restitution", "1.5", "(0, 1]"],
    );
}

#[test]
fn negative_friction() {
    refused(
        &BASE.replace("friction = 0.3", "friction = -0.1"),
        &["material.quartz.friction", "-0.1", ">= 0"],
    );
}

#[test]
fn particle_deep_in_a_wall() {
    // A container circle of radius 4 mm about (5, 5) mm; the disk's centre lies 0.1 mm
    // outside it, so it overlaps the wall by 0.6 mm, more than its 0.5 mm radius.
    let text = BASE.replace(
        "[[wall]]",
        "[[wall]]\nname = \"drum\"\nshape = \"circle\"\ncentre = [0.005, 0.005]\nradius = 0.004\ninside = true\n\n[[wall]]",
    )
    .replace("at = [0.005, 0.0006]", "at = [0.005, 0.0009]");
    refused(&text, &["particle 0", "drum", "radius"]);
}

#[test]
fn time_step_above_the_stable_limit() {
    refused(
        &BASE.replace("duration = 1.0e-7", "duration = 1.0e-7\ndt = 1.0e-6"),
        &["run.dt", "1e-6", "stable limit"],
    );
}

#[test]
fn not_toml() {
    refused("this is { not toml", &["s.toml", "line 1"]);
}

#[test]
fn unknown_material_reference() {
    refused(
        &BASE.replace(
            "material = \"quartz\"\ndisks",
            "material = \"granite\"\ndisks",
        ),
        &["particles[0].material", "granite", "quartz"],
    );
}

#[test]
fn check_json_reports_derived_figures() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("s.toml");
    std::fs::write(&file, BASE).unwrap();
    let o = grains(&["check", file.to_str().unwrap(), "--json"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let v: serde_json::Value = serde_json::from_str(&o.stdout).unwrap();
    assert_eq!(v["particles"], 1);
    assert!(v["dt"].as_f64().unwrap() > 0.0);
    assert!(v["dt"].as_f64().unwrap() <= v["dt_critical"].as_f64().unwrap());
    assert!(v["steps"].as_u64().unwrap() > 0);
    assert!(v["memory_bytes_estimate"].as_u64().unwrap() > 0);
}
