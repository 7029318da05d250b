//! The sheared cell end to end: a packing file becomes grains fixed to rigid boundaries
//! and a binder around them; the run writes the cell's history, plots and figures; bad
//! values of the cell and the packing are refused with one line naming key and value.

mod common;
use common::*;

/// A packing in the `grains pack` format: two lining disks (one per wall of the packing's
/// y, which swap_xy turns into the cell's x) and three grains.
const PACKING: &str = "# grains pack: test
# domain = rectangle lo_x=0e0 lo_y=0e0 hi_x=1e0 hi_y=1e0 periodic_x=true
# lining = 2
5e-1 1e-1 1e-1
5e-1 9e-1 1e-1
2e-1 5e-1 1.5e-1
6e-1 3e-1 1e-1
7e-1 7e-1 1.2e-1
";

const CELL: &str = r#"
engine = "mpm"
name = "cell"

[grid]
lo = [0.0, 0.0]
hi = [1.0, 1.0]
cell_size = 0.05
particles_per_cell = 2
periodic_y = 1.0

[[material]]
name = "grain"
model = "j2_plastic"
density = 1.0
bulk = 1.0
shear = 0.5
yield_stress = 0.05

[[material]]
name = "binder"
model = "maxwell"
density = 1.0
bulk = 0.5
prony = [{ shear = 0.05, time = 1.0 }]

[[body]]
name = "left"
material = "grain"
rigid = true
velocity_table = [[0.0, 0.0, 0.0], [0.5, 0.0, -0.02]]
geometry = { shape = "union", parts = [{ shape = "rectangle", lo = [0.0, 0.0], hi = [0.05, 1.0] }] }

[[body]]
name = "right"
material = "grain"
rigid = true
velocity_table = [[0.0, 0.0, 0.0], [0.5, 0.0, 0.02]]
geometry = { shape = "union", parts = [{ shape = "rectangle", lo = [0.95, 0.0], hi = [1.0, 1.0] }] }

[[body]]
name = "binder"
material = "binder"
geometry = { shape = "rectangle", lo = [0.0, 0.0], hi = [1.0, 1.0] }
minus = ["*"]

[[packing]]
file = "grains.txt"
material = "grain"
swap_xy = true
radius_scale = 0.9
lining = ["left", "right"]

[contact]
mu = 0.3

[[contact.pair]]
bodies = ["binder", "grain*"]
law = "bonded"
strength = 0.01
mu = 0.3

[shear]
left = ["left"]
right = ["right"]
lock_threshold = 1e-3
binder = "binder"

[run]
duration = 1.0

[output]
frames = 2
history = 20

[[check]]
kind = "contact_momentum_imbalance"
name = "contact_momentum_imbalance"
max = 1e-3
"#;

#[test]
fn a_packed_cell_with_binder_runs_and_reports_the_cell() {
    let (o, dir) = run_text(CELL, &[("grains.txt", PACKING)], &[]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let s = summary(dir.path());
    assert_eq!(s["status"], "completed", "{s}");
    let f = &s["figures"];
    for key in [
        "shear_strain_final",
        "locking_events",
        "inertial_number_mean",
        "debonded_length_final",
        "contact_imbalance",
    ] {
        assert!(f.get(key).is_some(), "figure {key} missing: {f}");
    }
    // The two lining disks went to the boundaries; the three grains are bodies.
    let h = std::fs::read_to_string(dir.path().join("out/history.csv")).unwrap();
    let head = h.lines().next().unwrap();
    for col in [
        "grain2_x",
        "left_force_y",
        "right_force_x",
        "boundary_work",
        "ledger",
    ] {
        assert!(head.split(',').any(|c| c == col), "column {col} missing");
    }
    assert!(!head.contains("grain3_x"));
    let plots = dir.path().join("out/plots");
    for p in [
        "shear_stress.png",
        "normal_stress.png",
        "energy_ledger.png",
        "debonded_length.png",
        "cell_initial.png",
        "cell_final.png",
        "bond_final.png",
    ] {
        assert!(plots.join(p).exists(), "{p} missing");
    }
    // Every plotted curve against strain is also data: the boundary stresses, the
    // ledger and the debonded length, one row per cell row.
    let csv = |p: &str| {
        let text = std::fs::read_to_string(plots.join(p)).unwrap();
        let mut lines = text.lines();
        let names: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
        let rows: Vec<Vec<f64>> = lines
            .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
            .collect();
        (names, rows)
    };
    let (names, rows) = csv("shear_stress.csv");
    assert_eq!(
        names[..3],
        ["shear strain γ", "left boundary", "right boundary"]
    );
    assert!(rows.len() > 2 && rows.iter().all(|r| r.len() == names.len()));
    for p in [
        "normal_stress.csv",
        "energy_ledger.csv",
        "debonded_length.csv",
    ] {
        let (_, r) = csv(p);
        assert_eq!(r.len(), rows.len(), "{p}");
    }
    assert!(s["checks"][0]["pass"] == true, "{s}");
}

/// `CELL` with `from` replaced by `to` (and the packing text `packing`) is refused.
fn refused_with(from: &str, to: &str, packing: &str, must: &[&str]) {
    assert!(CELL.contains(from), "the base lacks {from:?}");
    let (o, dir) = run_text(&CELL.replace(from, to), &[("grains.txt", packing)], &[]);
    assert_refused(&o, dir.path(), must);
}

#[test]
fn bad_cell_and_packing_values_are_refused() {
    // A grain of the packing outside the grid.
    let outside = PACKING.replace("7e-1 7e-1 1.2e-1", "7e-1 9.5e-1 1.2e-1");
    refused_with(
        "radius_scale = 0.9",
        "radius_scale = 0.9",
        &outside,
        &[
            "packing[0].file",
            "disk 4 at (0.95, 0.7)",
            "every grain must lie inside the grid",
            "after swap_xy",
        ],
    );
    let cases: [(&str, &str, &[&str]); 7] = [
        (
            "radius_scale = 0.9",
            "radius_scale = 1.5",
            &["packing[0].radius_scale = 1.5", "(0, 1]"],
        ),
        (
            "file = \"grains.txt\"",
            "file = \"missing.txt\"",
            &["packing[0].file = \"missing.txt\"", "cannot be used as a packing"],
        ),
        (
            "lining = [\"left\", \"right\"]",
            "lining = [\"binder\", \"right\"]",
            &["packing[0].lining[0] = \"binder\"", "rigid body", "union"],
        ),
        // A prescribed velocity on a deformable body: a boundary must be rigid ...
        (
            "left = [\"left\"]",
            "left = [\"binder\"]",
            &["shear.left[0] = \"binder\"", "must be a rigid body"],
        ),
        // ... and only a rigid body follows a velocity table.
        (
            "name = \"binder\"\nmaterial = \"binder\"",
            "name = \"binder\"\nmaterial = \"binder\"\nvelocity_table = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.1]]",
            &["body[2].velocity_table", "only a rigid body"],
        ),
        (
            "lock_threshold = 1e-3",
            "lock_threshold = -1.0",
            &["shear.lock_threshold = -1", "> 0"],
        ),
        (
            "bodies = [\"binder\", \"grain*\"]",
            "bodies = [\"binder\", \"sand*\"]",
            &["contact.pair[0].bodies = \"sand*\"", "matches no body"],
        ),
    ];
    for (from, to, must) in cases {
        refused_with(from, to, PACKING, must);
    }
}
