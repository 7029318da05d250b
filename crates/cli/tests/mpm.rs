//! The MPM front end end to end: bad input is refused with one line naming key, value
//! and what is allowed (exit 1, nothing written); a short bounce writes every output and
//! its checks; `grains check` and `grains bench mpm` answer.

mod common;
use common::*;

const BASE: &str = r#"
engine = "mpm"
name = "small"

[grid]
lo = [0.0, 0.0]
hi = [3.0, 3.0]
cell_size = 0.125
particles_per_cell = 2

[method]
shape = "gimp"
update = "usavg"

[walls]
top = { mu = 0.1 }
right = { mu = 0.1 }

[[material]]
name = "elastic"
model = "linear_elastic"
density = 1.0
bulk = 1.0
shear = 0.5

[[body]]
name = "cylinder"
material = "elastic"
geometry = { shape = "disk", centre = [1.0, 1.5], radius = 0.5 }
velocity = [0.1, 0.1]

[run]
duration = 14.0

[output]
frames = 5
history = 700

[[check]]
kind = "initial_energy"
name = "initial_energy"
tolerance = 0.005

[[check]]
kind = "impact_tangential_velocity"
name = "tangential_velocity_after_first_impact"
body = "cylinder"
impact = 1
tolerance = 0.10

[[check]]
kind = "impact_spin"
name = "spin_after_first_impact"
body = "cylinder"
impact = 1
tolerance = 0.15
"#;

#[test]
fn a_short_bounce_writes_everything_and_passes_its_checks() {
    let (o, dir) = run_text(BASE, &[], &[]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let out = dir.path().join("out");
    for f in [
        "scenario.toml",
        "history.csv",
        "summary.json",
        "frames/series.pvd",
        "frames/points_00000.vtp",
        "frames/grid_00000.vtu",
        "plots/energies.png",
        "plots/momenta.png",
        "plots/impact_cylinder_1.png",
        "plots/cylinder_motion.png",
    ] {
        assert!(out.join(f).exists(), "{f} missing");
    }
    let head = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let cols = head.lines().next().unwrap();
    for c in [
        "kinetic",
        "strain",
        "total",
        "momentum_x",
        "cylinder_omega",
        "cylinder_rotation",
        "cylinder_touch_wall",
        "cylinder_touch_body",
    ] {
        assert!(
            cols.split(',').any(|x| x == c),
            "column {c} missing in {cols}"
        );
    }
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let checks = s["checks"].as_array().unwrap();
    assert_eq!(checks.len(), 3);
    assert!(checks.iter().all(|c| c["pass"] == true), "{checks:?}");
    assert_eq!(s["figures"]["cylinder_impacts"][0]["walls"][0], "top");
    let vtp = std::fs::read(out.join("frames/points_00000.vtp")).unwrap();
    let text = String::from_utf8_lossy(&vtp);
    for a in [
        "\"stress\"",
        "\"pressure\"",
        "\"principal_stress_difference\"",
        "\"body\"",
        "\"velocity\"",
    ] {
        assert!(text.contains(a), "{a} missing from the VTP");
    }
}

#[test]
fn a_point_leaving_the_grid_stops_the_run_with_exit_3() {
    // No walls on the right: the cylinder flies out of the grid.
    let text = BASE
        .replace("right = { mu = 0.1 }", "")
        .replace("velocity = [0.1, 0.1]", "velocity = [1.0, 0.0]");
    let (o, dir) = run_text(&text, &[], &[]);
    assert_eq!(o.code, 3, "{}", o.stderr);
    assert!(o.stderr.contains("outside the grid"), "{}", o.stderr);
    let out = dir.path().join("out");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["status"], "unstable");
    assert!(out.join("frames/series.pvd").exists() && out.join("history.csv").exists());
}

#[test]
fn check_prints_the_stable_step() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("s.toml");
    std::fs::write(&file, BASE).unwrap();
    let o = grains(&["check", file.to_str().unwrap(), "--json"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let v: serde_json::Value = serde_json::from_str(&o.stdout).unwrap();
    let crit = v["dt_critical"].as_f64().unwrap();
    // h / (c + |v|) with c = √((K + 4G/3)/ρ) = 1.2910 and |v| = 0.1414.
    assert!(
        (crit - 0.125 / (1.290994 + 0.141421)).abs() < 1e-5,
        "{crit}"
    );
    assert_eq!(v["particles"], 208);
}

#[test]
fn bench_prints_particle_steps_last() {
    let small = [
        "bench",
        "mpm",
        "--particles",
        "2000",
        "--grid",
        "32",
        "--steps",
        "5",
    ];
    let bench = |extra: &[&str]| grains(&[&small[..], extra].concat());
    let o = bench(&["--threads", "1"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let out = o.stdout;
    assert!(
        out.trim_end()
            .lines()
            .last()
            .unwrap()
            .starts_with("particle-steps/s: "),
        "{out}"
    );
    let o = bench(&["--shape", "cubic"]);
    assert_eq!(o.code, 1);
    assert!(o.stderr.contains("--shape = cubic"), "{}", o.stderr);
    let o = bench(&["--material", "maxwell3"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(o.stdout.contains("material: maxwell3"), "{}", o.stdout);
    let o = bench(&["--material", "rubber"]);
    assert_eq!(o.code, 1);
    assert!(o.stderr.contains("--material = rubber"), "{}", o.stderr);
}

#[test]
fn bad_values_are_refused() {
    refused_all(
        BASE,
        &[
            (
                "radius = 0.5 }",
                "radius = 0.01 }",
                &["body[0].geometry", "holds no material point"],
            ),
            (
                "centre = [1.0, 1.5]",
                "centre = [2.8, 1.5]",
                &["body[0].geometry", "point at", "inside the grid"],
            ),
            ("bulk = 1.0", "bulk = 0.0", &["material[0].bulk = 0", "> 0"]),
            (
                "shear = 0.5",
                "shear = -0.5",
                &["material[0].shear = -0.5", "> 0"],
            ),
            (
                "density = 1.0",
                "density = 0.0",
                &["material[0].density = 0", "> 0"],
            ),
            (
                "duration = 14.0",
                "duration = 14.0\ndt = 0.1",
                &["run.dt = 0.1", "above the stable limit"],
            ),
            (
                "shape = \"gimp\"",
                "shape = \"cpdi\"",
                &[
                    "method.shape = \"cpdi\"",
                    "unknown shape function",
                    "\"gimp\"",
                ],
            ),
            (
                "update = \"usavg\"",
                "update = \"usx\"",
                &["method.update = \"usx\"", "unknown update scheme", "\"musl\""],
            ),
            ("engine = \"mpm\"", "engine = \"fem\"", &["engine", "\"fem\""]),
            (
                "cell_size = 0.125",
                "cell_size = 0.7",
                &["grid.cell_size = 0.7", "whole number"],
            ),
            (
                "material = \"elastic\"",
                "material = \"steel\"",
                &["body[0].material = \"steel\"", "must be one of"],
            ),
            (
                "top = { mu = 0.1 }",
                "top = { mu = -0.1 }",
                &["walls.top.mu = -0.1"],
            ),
            (
                "particles_per_cell = 2",
                "particles_per_cell = 0",
                &["grid.particles_per_cell = 0"],
            ),
            ("shear = 0.5", "shear = 0.5\nyoung = 1.0", &["young"]),
            (
                "impact = 1\ntolerance = 0.15",
                "impact = 0\ntolerance = 0.15",
                &["check[2].impact = 0"],
            ),
            (
                "frames = 5",
                "frames = 5\ncheckpoint_every = 10",
                &["output.checkpoint_every", "DEM runs only"],
            ),
            // A second body overlapping the first.
            (
                "[run]",
                "[[body]]\nname = \"other\"\nmaterial = \"elastic\"\ngeometry = { shape = \"disk\", centre = [1.3, 1.5], radius = 0.5 }\n\n[run]",
                &["body[1].geometry", "overlaps body \"cylinder\""],
            ),
        ],
    );
    assert_eq!(grains(&["run", "/nonexistent/x.toml"]).code, 1);
}

/// Every key of the materials with memory: a hot elastic disk bonded to a J2 ring, a
/// Maxwell binder filling the box around them (`minus = ["*"]`), a rigid lid following
/// a velocity table; coarse (20 × 20 cells), cooled fast enough to debond in 8 s.
const LAYERS: &str = r#"
engine = "mpm"
name = "layers"

[grid]
lo = [-1.25, -1.25]
hi = [1.25, 1.25]
cell_size = 0.125
particles_per_cell = 2

[[material]]
name = "hot"
model = "linear_elastic"
density = 1.0
bulk = 1.0
shear = 0.5
expansion = 5e-3

[[material]]
name = "ring"
model = "j2_plastic"
density = 1.0
bulk = 1.0
shear = 0.5
yield_stress = 1.0
hardening = 0.1

[[material]]
name = "binder"
model = "maxwell"
density = 1.0
bulk = 1.0
shear = 0.0
prony = [{ shear = 0.5, time = 10.0 }]

[[body]]
name = "inner"
material = "hot"
geometry = { shape = "disk", centre = [0.0, 0.0], radius = 0.5 }
temperature = { history = "table", points = [[0.0, 0.0], [3.0, -5.0], [6.0, -10.0]] }

[[body]]
name = "outer"
material = "ring"
geometry = { shape = "annulus", centre = [0.0, 0.0], inner = 0.5, outer = 1.0 }

[[body]]
name = "binder"
material = "binder"
geometry = { shape = "rectangle", lo = [-1.1, -1.1], hi = [1.1, 1.0] }
minus = ["*"]

[[body]]
name = "lid"
material = "hot"
geometry = { shape = "rectangle", lo = [-1.1, 1.0], hi = [1.1, 1.2] }
rigid = true
velocity_table = [[0.0, 0.0, 0.0], [4.0, 0.0, -0.001], [8.0, 0.0, 0.0]]

[contact]
law = "coulomb"
mu = 0.0

[[contact.pair]]
bodies = ["inner", "outer"]
law = "bonded"
strength = 2.025e-2

[run]
duration = 8.0

[output]
frames = 4
history = 400
"#;

#[test]
fn materials_with_memory_write_their_fields_and_debond() {
    let (o, dir) = run_text(LAYERS, &[], &[]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let out = dir.path().join("out");
    let head = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let cols: Vec<&str> = head.lines().next().unwrap().split(',').collect();
    for c in [
        "dissipated",
        "thermal_work",
        "balance",
        "inner_temperature",
        "inner_mean_stress",
        "inner_debonded_length",
        "inner_surface_length",
        "outer_plastic_max",
        "outer_dissipated",
        "outer_debonded_length",
        "binder_dissipated",
    ] {
        assert!(cols.contains(&c), "column {c} missing in {cols:?}");
    }
    // Only where they mean something: no temperature on the ring, no bond on the binder.
    for c in [
        "outer_temperature",
        "binder_debonded_length",
        "inner_plastic_max",
    ] {
        assert!(!cols.contains(&c), "column {c} should not be written");
    }
    let vtp = std::fs::read(out.join("frames/points_00000.vtp")).unwrap();
    let text = String::from_utf8_lossy(&vtp);
    for a in [
        "\"bond\"",
        "\"plastic_strain\"",
        "\"dissipated_density\"",
        "\"temperature\"",
        "\"thermal_work\"",
    ] {
        assert!(text.contains(a), "{a} missing from the VTP");
    }
    for f in [
        "plots/bond_1_before_onset.png",
        "plots/bond_4_final.png",
        "plots/debonded_length.png",
        "plots/debond_front.png",
    ] {
        assert!(out.join(f).exists(), "{f} missing");
    }
    let s = summary(dir.path());
    let onset = s["figures"]["debond_onset_time"].as_f64().unwrap();
    assert!(onset > 0.0 && onset < 8.0, "{onset}");
    assert!(s["figures"]["initiation_sites"].as_u64().unwrap() >= 1);
    // The binder fills the box exactly where the disk, the ring and the lid are not.
    let o = grains_in(Some(dir.path()), &["check", "s.toml", "--json"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let v: serde_json::Value = serde_json::from_str(&o.stdout).unwrap();
    let binder = &v["bodies"][2];
    let area = 2.2 * 2.1 - std::f64::consts::PI;
    assert!(
        (binder["area"].as_f64().unwrap() / area - 1.0).abs() < 1e-3,
        "{binder}"
    );
}

#[test]
fn bad_material_thermal_and_bond_values_are_refused() {
    refused_all(
        LAYERS,
        &[
            (
                "yield_stress = 1.0",
                "yield_stress = -1.0",
                &["material[1].yield_stress = -1", "> 0"],
            ),
            (
                "yield_stress = 1.0",
                "yield_stress = nan",
                &["material[1].yield_stress = NaN", "finite"],
            ),
            (
                "hardening = 0.1",
                "hardening = -0.1",
                &["material[1].hardening = -0.1", ">= 0"],
            ),
            (
                "hardening = 0.1",
                "hardening = inf",
                &["material[1].hardening = inf", "finite"],
            ),
            (
                "time = 10.0",
                "time = -10.0",
                &["material[2].prony[0].time = -10", "> 0"],
            ),
            (
                "time = 10.0",
                "time = nan",
                &["material[2].prony[0].time = NaN", "finite"],
            ),
            (
                "prony = [{ shear = 0.5, time = 10.0 }]",
                "prony = []",
                &["material[2].prony = []", "at least one Prony term"],
            ),
            (
                "expansion = 5e-3",
                "expansion = -5e-3",
                &["material[0].expansion = -0.005", ">= 0"],
            ),
            (
                "expansion = 5e-3",
                "expansion = nan",
                &["material[0].expansion = NaN", "finite"],
            ),
            (
                "[3.0, -5.0], [6.0, -10.0]",
                "[6.0, -5.0], [3.0, -10.0]",
                &[
                    "body[0].temperature.points[2] = [3.0, -10.0]",
                    "increase strictly",
                ],
            ),
            (
                "points = [[0.0, 0.0], [3.0, -5.0], [6.0, -10.0]]",
                "points = []",
                &["body[0].temperature.points = []", "at least one"],
            ),
            (
                "[4.0, 0.0, -0.001], [8.0, 0.0, 0.0]",
                "[8.0, 0.0, -0.001], [4.0, 0.0, 0.0]",
                &[
                    "body[3].velocity_table[2] = [4.0, 0.0, 0.0]",
                    "increase strictly",
                ],
            ),
            (
                "minus = [\"*\"]",
                "minus = [\"grain\"]",
                &["body[2].minus[0] = \"grain\"", "must be \"*\" or one of"],
            ),
            (
                "minus = [\"*\"]",
                "minus = [\"inner\"]",
                &["body[2].geometry", "overlaps body \"outer\""],
            ),
            (
                "strength = 2.025e-2",
                "strength = -1.0",
                &["contact.pair[0].strength = -1", ">= 0"],
            ),
            (
                "law = \"bonded\"\nstrength = 2.025e-2",
                "law = \"bonded\"",
                &["contact.pair[0].strength = (missing)", "needs a bond strength"],
            ),
            (
                "law = \"bonded\"",
                "law = \"coulomb\"",
                &["contact.pair[0].strength = 0.02025", "only a \"bonded\" law"],
            ),
            (
                "rigid = true\nvelocity_table",
                "velocity_table",
                &["body[3].velocity_table", "only a rigid body"],
            ),
            (
                "[[contact.pair]]",
                "[[check]]\nkind = \"shear_stress_plateau\"\nname = \"p\"\nbody = \"outer\"\nregion = { lo = [0.0, 0.0], hi = [1.0, 1.0] }\ntolerance = 0.01\n\n[[contact.pair]]",
                &["check[0].body = \"outer\"", "hardening = 0"],
            ),
            (
                "[[contact.pair]]",
                "[[check]]\nkind = \"relaxation_time\"\nname = \"r\"\nbody = \"inner\"\nregion = { lo = [0.0, 0.0], hi = [1.0, 1.0] }\nafter = 1.0\ntolerance = 0.02\n\n[[contact.pair]]",
                &["check[0].body = \"inner\"", "one Prony term"],
            ),
            (
                "[[contact.pair]]",
                "[[check]]\nkind = \"debond_onset_time\"\nname = \"d\"\ninner = \"binder\"\nouter = \"outer\"\ntolerance = 0.02\n\n[[contact.pair]]",
                &["check[0].inner = \"binder\"", "must be a disk"],
            ),
        ],
    );
    // A bond strength on a body with no partner: the only body, bonded by default.
    let alone = LAYERS
        .split("[[body]]")
        .take(2)
        .collect::<Vec<_>>()
        .join("[[body]]")
        + "\n[contact]\nlaw = \"bonded\"\nstrength = 5.0\n\n[run]\nduration = 1.0\n";
    refused(
        &alone,
        &[
            "contact.strength = 5",
            "a bond needs two bodies; there is only one",
        ],
    );
}

#[test]
fn material_examples_pass_their_checks() {
    for example in [
        "mpm/j2_simple_shear.toml",
        "mpm/maxwell_relaxation.toml",
        "mpm/thermal_free_expansion.toml",
        "bardenhagen1998/concentric_cylinders_debond_small.toml",
    ] {
        let (o, s) = run_example(example);
        assert_eq!(o.code, 0, "{example}: {}", o.stderr);
        let checks = s["checks"].as_array().unwrap();
        assert!(!checks.is_empty(), "{example}");
        assert!(
            checks.iter().all(|c| c["pass"] == true),
            "{example}: {checks:?}"
        );
    }
}
