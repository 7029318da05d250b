//! Every kind of bad input is refused with one line naming the key, the value and what
//! is allowed, exit code 1, and no output directory; what is merely huge gets a
//! warning with its estimate; a run that goes unstable never passes a check.

mod common;
use common::*;

const BASE: &str = ONE_DISK;

#[test]
fn the_base_scenario_runs() {
    let (out, dir) = run_text(BASE, &[], &[]);
    assert_eq!(out.code, 0, "{}", out.stderr);
    assert!(dir.path().join("out").exists());
}

#[test]
fn bad_values_are_refused() {
    refused_all(
        BASE,
        &[
            (
                "friction = 0.3",
                "friction = 0.3\nfrcition = 0.3",
                &["frcition", "expected"],
            ),
            (
                "density = 2560.0",
                "density = 0.0",
                &["material.quartz.density", "0", "> 0"],
            ),
            (
                "youngs = 72.0e9",
                "youngs = -1.0",
                &["material.quartz.youngs", "-1", "> 0"],
            ),
            ("radius = 0.0005", "radius = 0.0", &["radius", "0", "> 0"]),
            (
                "duration = 1.0e-7",
                "duration = 1.0e-7\ndt = -1.0e-9",
                &["run.dt", "-1e-9", "> 0"],
            ),
            (
                "restitution = 0.5",
                "restitution = 0.0",
                &["material.quartz.restitution", "0", "(0, 1]"],
            ),
            (
                "restitution = 0.5",
                "restitution = 1.5",
                &["material.quartz.restitution", "1.5", "(0, 1]"],
            ),
            (
                "friction = 0.3",
                "friction = -0.1",
                &["material.quartz.friction", "-0.1", ">= 0"],
            ),
            (
                "duration = 1.0e-7",
                "duration = 1.0e-7\ndt = 1.0e-6",
                &["run.dt", "1e-6", "stable limit"],
            ),
            (
                "material = \"quartz\"\ndisks",
                "material = \"granite\"\ndisks",
                &["particles[0].material", "granite", "quartz"],
            ),
            // A particle outside the (non-periodic) domain.
            (
                "at = [0.005, 0.0006]",
                "at = [0.015, 0.0006]",
                &["particle 0", "x = 0.015", "inside the domain"],
            ),
            // Coincident disks.
            (
                "radius = 0.0005 }]",
                "radius = 0.0005 }, { at = [0.005, 0.0006], radius = 0.0005 }]",
                &["particles 0 and 1", "overlap inf", "at most 0.5"],
            ),
            // Deeply overlapping disks.
            (
                "radius = 0.0005 }]",
                "radius = 0.0005 }, { at = [0.0055, 0.0006], radius = 0.0005 }]",
                &["particles 0 and 1", "overlap 1.000", "at most 0.5"],
            ),
        ],
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
fn not_toml() {
    refused("this is { not toml", &["s.toml", "line 1"]);
}

/// Ten billion disks: refused with the estimate before anything is built, by `run`,
/// `check` and `bench`.
#[test]
fn too_large_for_memory() {
    let huge = BASE
        .replace("hi = [0.01, 0.01]", "hi = [1.0e3, 1.0e3]")
        .replace(
            "source = \"list\"\nmaterial = \"quartz\"\ndisks = [{ at = [0.005, 0.0006], radius = 0.0005 }]",
            "source = \"lattice\"\nmaterial = \"quartz\"\nregion = { lo = [0.0, 0.0], hi = [1.0e3, 1.0e3] }\ncount = 10000000000\nradius = { distribution = \"constant\", value = 4.0e-6 }",
        );
    refused(&huge, &["particles", "10000000000 particles", "of memory"]);
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("s.toml");
    std::fs::write(&file, &huge).unwrap();
    let o = grains(&["check", file.to_str().unwrap()]);
    assert_eq!(o.code, 1, "{}", o.stderr);
    assert!(o.stderr.contains("of memory"), "{}", o.stderr);
    let o = grains(&["bench", "dem", "--particles", "10000000000", "--steps", "1"]);
    assert_eq!(o.code, 1, "{}", o.stderr);
    assert!(
        o.stderr
            .contains("--particles: about 10000000000 particles"),
        "{}",
        o.stderr
    );
}

/// A run of 10¹⁴ steps: `check` warns with its estimate.
#[test]
fn an_endless_run_is_announced() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("s.toml");
    std::fs::write(&file, BASE.replace("duration = 1.0e-7", "duration = 1.0e5")).unwrap();
    let o = grains(&["check", file.to_str().unwrap()]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let warning = o.stdout.lines().find(|l| l.starts_with("warning")).unwrap();
    assert!(
        warning.contains("steps, about") && warning.contains("days"),
        "{warning}"
    );
}

/// A packing spec is not a scenario, and a scenario is not a packing spec.
#[test]
fn the_wrong_kind_of_file() {
    let spec = "name = \"p\"\n[domain]\nshape = \"disk\"\nradius = 0.01\n[sizes]\ndistribution = \"gaussian\"\nd0 = 1e-3\ndelta = 0.1\n";
    refused(spec, &["packing spec", "grains pack"]);
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("s.toml");
    std::fs::write(&file, spec).unwrap();
    let o = grains(&["check", file.to_str().unwrap()]);
    assert_eq!(o.code, 1);
    assert!(o.stderr.contains("grains pack"), "{}", o.stderr);
    std::fs::write(&file, BASE).unwrap();
    let o = grains_in(Some(dir.path()), &["pack", "s.toml", "--out", "out"]);
    assert_eq!(o.code, 1);
    assert!(o.stderr.contains("grains run"), "{}", o.stderr);
    assert!(!dir.path().join("out").exists());
}

/// Two disks thrown at each other ten thousand times too fast: the run stops unstable
/// (exit 3) and its check fails, whatever it measured.
#[test]
fn an_unstable_run_never_passes_a_check() {
    let text = BASE
        .replace("gravity = [0.0, -9.81]", "gravity = [0.0, 0.0]")
        .replace(
            "disks = [{ at = [0.005, 0.0006], radius = 0.0005 }]",
            "disks = [{ at = [0.004, 0.005], radius = 0.0005, velocity = [1.0e4, 0.0] }, { at = [0.006, 0.005], radius = 0.0005, velocity = [-1.0e4, 0.0] }]",
        )
        .replace("duration = 1.0e-7", "duration = 1.0e-5")
        + "\n[[check]]\nkind = \"restitution\"\nname = \"e\"\nparticles = [0, 1]\ntolerance = 1e9\n";
    let (out, dir) = run_text(&text, &[], &[]);
    assert_eq!(out.code, 3, "{}", out.stderr);
    let s = summary(dir.path());
    assert_eq!(s["status"], "unstable");
    assert_eq!(s["checks"][0]["pass"], false, "{}", s["checks"][0]);
}

#[test]
fn check_json_reports_derived_figures() {
    let v = check_json(BASE);
    assert_eq!(v["particles"], 1);
    assert!(v["dt"].as_f64().unwrap() > 0.0);
    assert!(v["dt"].as_f64().unwrap() <= v["dt_critical"].as_f64().unwrap());
    assert!(v["steps"].as_u64().unwrap() > 0);
    assert!(v["memory_bytes_estimate"].as_u64().unwrap() > 0);
    assert!(v["wall_time_estimate_s"].as_f64().unwrap() >= 0.0);
}
