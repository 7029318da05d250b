//! The replayable list of bad inputs, as a new user would type them: every one across
//! `run`, `check`, `pack`, `analyze`, `resume` and `bench` must end with exit code 1,
//! one error line naming what was wrong, no panic, and nothing written anywhere in the
//! directory it ran in (the tree is compared before and after).

mod common;
use common::*;
#[path = "refusals/dem3d.rs"]
mod dem3d;
#[path = "refusals/others.rs"]
mod others;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A small DEM scenario that runs (one disk resting on a floor).
const DEM: &str = ONE_DISK;

/// A small MPM scenario: one elastic disk in a walled box.
const MPM: &str = r#"engine = "mpm"
name = "bad_mpm"

[grid]
lo = [0.0, 0.0]
hi = [2.0, 2.0]
cell_size = 0.1
particles_per_cell = 2

[[material]]
name = "soft"
model = "linear_elastic"
density = 1.0
bulk = 1.0
shear = 0.5

[[body]]
name = "disk"
material = "soft"
geometry = { shape = "disk", centre = [1.0, 1.0], radius = 0.5 }

[run]
duration = 0.1

[[check]]
kind = "energy_balance"
name = "energy_balance"
max = 0.01
"#;

/// A small FEM–DEM scenario: a charge in a lattice ring.
const FEM_DEM: &str = r#"engine = "fem_dem"
name = "bad_ring"

[charge]
explosive = "tnt_llnl1985"
radius = 0.010

[charge.mesh]
size_edge = 0.6e-3
size_centre = 0.8e-3

[ring]
material = "quartz"
inner_radius = 0.010
outer_radius = 0.030

[ring.packing]
source = "lattice"
d0 = 0.4e-3
spread = 0.03
lining = 0.6
seed = 1

[[material]]
name = "quartz"
density = 2560.0
youngs = 72.0e9
poisson = 0.27
friction = 0.3
restitution = 0.3723

[run]
duration = 1.0e-6
"#;

/// A small packing spec.
const SPEC: &str = r#"name = "bad_pack"
seed = 1

[domain]
shape = "annulus"
r_in = 0.010
r_out = 0.011

[sizes]
distribution = "uniform"
d0 = 95.6e-6
delta = 0.177

[protocol]
target_fraction = 0.8
rate = 1e-4
"#;

/// One bad input: the files it needs (paths relative to a fresh directory), the
/// command, and what its error line must name.
struct Case {
    /// What was changed, for the failure report.
    label: String,
    files: Vec<(String, Vec<u8>)>,
    args: Vec<String>,
    expect: Vec<String>,
}

fn case(files: &[(&str, &str)], args: &[&str], expect: &[&str]) -> Case {
    Case {
        label: String::new(),
        files: files
            .iter()
            .map(|(p, t)| (p.to_string(), t.as_bytes().to_vec()))
            .collect(),
        args: args.iter().map(|s| s.to_string()).collect(),
        expect: expect.iter().map(|s| s.to_string()).collect(),
    }
}

/// `text` with `from` replaced by `to` (which must occur).
fn edit(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "{from:?} not in the base text");
    text.replacen(from, to, 1)
}

/// `grains run s.toml` of `base` edited, refused naming `expect`.
fn run_edit(base: &str, from: &str, to: &str, expect: &[&str]) -> Case {
    let text = edit(base, from, to);
    labelled(to, case(&[("s.toml", &text)], &["run", "s.toml"], expect))
}

fn labelled(label: &str, mut c: Case) -> Case {
    c.label = label.replace('\n', "⏎");
    c
}

/// The same edit given to `grains check`.
fn check_edit(base: &str, from: &str, to: &str, expect: &[&str]) -> Case {
    let text = edit(base, from, to);
    labelled(to, case(&[("s.toml", &text)], &["check", "s.toml"], expect))
}

/// `grains pack p.toml` of the spec edited.
fn pack_edit(from: &str, to: &str, expect: &[&str]) -> Case {
    let text = edit(SPEC, from, to);
    labelled(to, case(&[("p.toml", &text)], &["pack", "p.toml"], expect))
}

/// Every file under `dir` with its size, to tell whether anything was written.
fn tree(dir: &Path) -> BTreeMap<PathBuf, u64> {
    let mut out = BTreeMap::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            let m = std::fs::symlink_metadata(&p).unwrap();
            if m.is_dir() {
                todo.push(p.clone());
            }
            out.insert(p.strip_prefix(dir).unwrap().to_path_buf(), m.len());
        }
    }
    out
}

/// Runs one case in `root/work` (so that an escaping output would land inside
/// `root`); `None` when it was refused as promised, else what went wrong.
fn replay(c: &Case) -> Option<String> {
    let root = tempfile::tempdir().unwrap();
    let work = root.path().join("work");
    std::fs::create_dir(&work).unwrap();
    for (p, body) in &c.files {
        let p = work.join(p);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, body).unwrap();
    }
    let before = tree(root.path());
    let args: Vec<&str> = c.args.iter().map(String::as_str).collect();
    let o = grains_in(Some(&work), &args);
    let after = tree(root.path());
    let errors: Vec<&str> = o.stderr.lines().filter(|l| l.contains("error")).collect();
    let others: Vec<&str> = o
        .stderr
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.contains("error") && !l.contains("warning"))
        .collect();
    let what = format!("grains {} [{}]", c.args.join(" "), c.label);
    if o.code != 1 {
        return Some(format!("{what}: exit {} (stderr {:?})", o.code, o.stderr));
    }
    if o.stderr.contains("panicked") {
        return Some(format!("{what}: panicked: {}", o.stderr));
    }
    if errors.len() != 1 || !others.is_empty() {
        return Some(format!("{what}: not one error line: {:?}", o.stderr));
    }
    if let Some(s) = c.expect.iter().find(|s| !errors[0].contains(s.as_str())) {
        return Some(format!("{what}: {:?} does not name {s:?}", errors[0]));
    }
    if before != after {
        let new: Vec<_> = after.keys().filter(|k| !before.contains_key(*k)).collect();
        return Some(format!("{what}: wrote {new:?}"));
    }
    None
}

/// Bad names: every name that becomes an output path is one safe path component.
fn names(all: &mut Vec<Case>) {
    let bad = [
        ("../../escaped", "'/'"),
        ("/tmp/grains_absolute", "'/'"),
        ("", "empty"),
        ("  ", "empty"),
        ("a/b", "'/'"),
        ("a\\\\b", "'\\'"),
        ("..", "'.'"),
        (".", "'.'"),
        (".hidden", "'.'"),
        ("tab\\there", "control"),
        ("line\\nbreak", "control"),
        ("nul\\u0000", "control"),
        ("c:drive", "':'"),
    ];
    for (name, why) in bad {
        let line = format!("name = \"{name}\"");
        all.push(run_edit(DEM, "name = \"bad\"", &line, &["name", why]));
        all.push(check_edit(DEM, "name = \"bad\"", &line, &["name", why]));
        all.push(pack_edit("name = \"bad_pack\"", &line, &["name", why]));
    }
    for (name, why) in [("../up", "'/'"), ("", "empty"), ("/abs", "'/'")] {
        let line = format!("name = \"{name}\"");
        all.push(run_edit(MPM, "name = \"bad_mpm\"", &line, &["name", why]));
        all.push(run_edit(
            FEM_DEM,
            "name = \"bad_ring\"",
            &line,
            &["name", why],
        ));
    }
    all.push(run_edit(
        MPM,
        "name = \"disk\"",
        "name = \"../disk\"",
        &["body[0].name", "'/'"],
    ));
    all.push(run_edit(
        MPM,
        "name = \"energy_balance\"",
        "name = \"../../plot\"",
        &["check[0].name", "'/'"],
    ));
    // A scenario naming a packing spec whose name escapes the packing cache.
    let spec = edit(SPEC, "name = \"bad_pack\"", "name = \"../../cache_escape\"");
    let ring = edit(
        FEM_DEM,
        "source = \"lattice\"\nd0 = 0.4e-3\nspread = 0.03\nlining = 0.6\nseed = 1",
        "source = \"spec\"\nspec = \"p.toml\"",
    );
    all.push(case(
        &[("s.toml", &ring), ("p.toml", &spec)],
        &["run", "s.toml"],
        &["'/'"],
    ));
}

/// Command-line mistakes (clap's and ours).
fn arguments(all: &mut Vec<Case>) {
    let dem = [("s.toml", DEM)];
    let spec = [("p.toml", SPEC)];
    for args in [
        &["frobnicate"][..],
        &["run", "--frobnicate"],
        &["run", "s.toml", "--threads", "abc"],
        &["run", "s.toml", "--threads", "-1"],
        &["run", "s.toml", "--threads", "0"],
        &["run", "s.toml", "--stop-at-step", "-1"],
        &["run", "s.toml", "--stop-at-step", "x"],
        &["run", "s.toml", "extra.toml"],
        &["run", "s.toml", "--out"],
        &["check"],
        &["check", "s.toml", "--threads", "0"],
        &["check", "s.toml", "--json=maybe"],
        &["pack"],
        &["pack", "p.toml", "--threads", "0"],
        &["analyze"],
        &["resume"],
        &["bench"],
        &["bench", "lbm"],
        &["bench", "dem", "--steps", "0"],
        &["bench", "dem", "--steps", "-5"],
        &["bench", "dem", "--particles", "0"],
        &["bench", "dem", "--tile", "0"],
        &["bench", "dem", "--threads", "0"],
        &["bench", "dem", "--lammps-data", "missing.data"],
        &["bench", "dem", "--dim", "4"],
        &["bench", "dem", "--dim", "3"],
        &[
            "bench",
            "dem",
            "--dim",
            "3",
            "--lammps-data",
            "missing.data",
        ],
        &["bench", "mpm", "--steps", "0"],
        &["bench", "mpm", "--particles", "0"],
        &["bench", "mpm", "--grid", "0"],
        &["bench", "mpm", "--bodies", "3"],
        &["bench", "mpm", "--shape", "cubic"],
        &["bench", "mpm", "--update", "flip"],
        &["bench", "mpm", "--material", "rubber"],
        &["bench", "mpm", "--threads", "0"],
    ] {
        let files: &[(&str, &str)] = if args[0] == "pack" { &spec } else { &dem };
        all.push(case(files, args, &[]));
    }
    all.push(case(&[], &["run", "missing.toml"], &["missing.toml"]));
    // A data file of the other dimension, each way: the line names the telling value.
    let flat = "t\n\n1 atoms\n\n0 4 xlo xhi\n0 4 ylo yhi\n-0.5 0.5 zlo zhi\n\nAtoms # sphere\n\n1 1 1 1 2 2 0\n";
    let deep = flat.replace("2 2 0\n", "2 2 0.5\n");
    all.push(case(
        &[("flat.data", flat)],
        &["bench", "dem", "--dim", "3", "--lammps-data", "flat.data"],
        &["flat.data", "z = 0"],
    ));
    all.push(case(
        &[("deep.data", deep.as_str())],
        &["bench", "dem", "--lammps-data", "deep.data"],
        &["deep.data", "z = 0.5"],
    ));
    let from_deep = DEM.replacen(
        "[[wall]]",
        "[[particles]]\nsource = \"lammps_data\"\nmaterial = \"quartz\"\npath = \"deep.data\"\n\n[[wall]]",
        1,
    );
    all.push(case(
        &[("s.toml", from_deep.as_str()), ("deep.data", deep.as_str())],
        &["run", "s.toml"],
        &["particles[1].path", "z = 0.5"],
    ));
    all.push(case(&[], &["check", "missing.toml"], &["missing.toml"]));
    all.push(case(&[], &["pack", "missing.toml"], &["missing.toml"]));
    all.push(case(&[], &["analyze", "missing.txt"], &["missing.txt"]));
    all.push(case(&[], &["resume", "missing_dir"], &["missing_dir"]));
    all.push(case(&[("d/x", "")], &["run", "d"], &["d"]));
    all.push(case(&[("d/x", "")], &["check", "d"], &["d"]));
    all.push(case(&[("s.toml", "")], &["run", "s.toml"], &["s.toml"]));
    all.push(case(
        &[("s.toml", "\u{0}\u{1}binary")],
        &["check", "s.toml"],
        &["s.toml"],
    ));
    all.push(case(
        &[("s.toml", "name = ")],
        &["run", "s.toml"],
        &["s.toml"],
    ));
    all.push(case(
        &[("s.toml", DEM), ("a.txt", "0 0 1\n")],
        &["analyze", "a.txt", "--times", "1e-6"],
        &["--times"],
    ));
    // Outputs that cannot be written, refused before anything is computed.
    all.push(case(
        &[("p.toml", SPEC), ("file", "")],
        &["pack", "p.toml", "--out", "file"],
        &["file"],
    ));
    all.push(case(
        &[("p.toml", SPEC), ("file", "")],
        &["pack", "p.toml", "--out", "file/sub"],
        &["file/sub"],
    ));
    all.push(case(
        &[("s.toml", DEM), ("file", "")],
        &["run", "s.toml", "--out", "file"],
        &["file"],
    ));
    all.push(case(
        &[("s.toml", DEM), ("file", "")],
        &["run", "s.toml", "--out", "file/sub"],
        &["file/sub"],
    ));
    all.push(case(
        &[("a.txt", "0 0 0.5\n2 0 0.5\n"), ("file", "")],
        &["analyze", "a.txt", "--out", "file"],
        &["file"],
    ));
    // Analysis inputs that are not what they claim.
    for (name, body) in [
        ("a.txt", ""),
        ("a.txt", "x y r\n"),
        ("a.txt", "1 2\n"),
        ("a.txt", "0 0 -1\n"),
        ("a.txt", "nan 0 1\n"),
        ("a.vtp", "<VTKFile>"),
        ("a.vtp", ""),
    ] {
        all.push(case(&[(name, body)], &["analyze", name], &[name]));
    }
    // Run directories that cannot be resumed.
    let finished = r#"{"status": "completed"}"#;
    all.push(case(&[("r/x", "")], &["resume", "r"], &["r"]));
    all.push(case(
        &[("r/scenario.toml", DEM), ("r/summary.json", finished)],
        &["resume", "r"],
        &["already finished"],
    ));
    all.push(case(
        &[("r/scenario.toml", DEM)],
        &["resume", "r"],
        &["checkpoint"],
    ));
    all.push(case(
        &[
            ("r/scenario.toml", DEM),
            ("r/checkpoint.bin", "not a checkpoint"),
        ],
        &["resume", "r"],
        &["checkpoint"],
    ));
    all.push(case(
        &[("r/scenario.toml", MPM), ("r/checkpoint.bin", "x")],
        &["resume", "r"],
        &["engine"],
    ));
    all.push(case(
        &[("r/scenario.toml", "not toml {"), ("r/checkpoint.bin", "x")],
        &["resume", "r"],
        &["scenario.toml"],
    ));
}

/// Bad values in a DEM scenario, given to `run` (and a few to `check`).
fn dem_values(all: &mut Vec<Case>) {
    let edits: &[(&str, &str, &[&str])] = &[
        (
            "friction = 0.3",
            "friction = 0.3\nfrcition = 0.3",
            &["frcition"],
        ),
        ("density = 2560.0", "density = 0.0", &["density"]),
        ("density = 2560.0", "density = -1.0", &["density"]),
        ("density = 2560.0", "density = nan", &["density"]),
        ("density = 2560.0", "density = \"heavy\"", &["density"]),
        ("youngs = 72.0e9", "youngs = -1.0", &["youngs"]),
        ("youngs = 72.0e9", "youngs = inf", &["youngs"]),
        ("poisson = 0.27", "poisson = 0.5", &["poisson"]),
        ("poisson = 0.27", "poisson = -1.5", &["poisson"]),
        ("radius = 0.0005", "radius = 0.0", &["radius"]),
        ("radius = 0.0005", "radius = -0.0005", &["radius"]),
        ("radius = 0.0005", "radius = nan", &["radius"]),
        ("restitution = 0.5", "restitution = 0.0", &["restitution"]),
        ("restitution = 0.5", "restitution = 1.5", &["restitution"]),
        ("friction = 0.3", "friction = -0.1", &["friction"]),
        ("friction = 0.3", "friction = nan", &["friction"]),
        ("duration = 1.0e-7", "duration = 0.0", &["duration"]),
        ("duration = 1.0e-7", "duration = -1.0", &["duration"]),
        ("duration = 1.0e-7", "duration = nan", &["duration"]),
        (
            "duration = 1.0e-7",
            "duration = 1.0e-7\ndt = -1.0e-9",
            &["run.dt"],
        ),
        (
            "duration = 1.0e-7",
            "duration = 1.0e-7\ndt = 0.0",
            &["run.dt"],
        ),
        (
            "duration = 1.0e-7",
            "duration = 1.0e-7\ndt = 1.0e-6",
            &["run.dt"],
        ),
        (
            "duration = 1.0e-7",
            "duration = 1.0e-7\ndt = 1.0e-9\nsafety = 0.5",
            &["run.dt", "run.safety"],
        ),
        (
            "duration = 1.0e-7",
            "duration = 1.0e-7\nsafety = 0.0",
            &["safety"],
        ),
        (
            "duration = 1.0e-7",
            "duration = 1.0e-7\nsafety = 2.0",
            &["safety"],
        ),
        (
            "material = \"quartz\"\ndisks",
            "material = \"granite\"\ndisks",
            &["granite"],
        ),
        (
            "at = [0.005, 0.0006]",
            "at = [0.015, 0.0006]",
            &["particle 0"],
        ),
        (
            "at = [0.005, 0.0006]",
            "at = [0.005, -0.0006]",
            &["particle 0"],
        ),
        ("at = [0.005, 0.0006]", "at = [0.005, 0.0001]", &["floor"]),
        ("at = [0.005, 0.0006]", "at = [0.005, 0.00015]", &["floor"]),
        ("at = [0.005, 0.0006]", "at = [0.005]", &["particles"]),
        (
            "radius = 0.0005 }]",
            "radius = 0.0005 }, { at = [0.005, 0.0006], radius = 0.0005 }]",
            &["particles 0 and 1"],
        ),
        (
            "radius = 0.0005 }]",
            "radius = 0.0005 }, { at = [0.0055, 0.0006], radius = 0.0005 }]",
            &["particles 0 and 1"],
        ),
        ("hi = [0.01, 0.01]", "hi = [0.0, 0.01]", &["domain"]),
        ("hi = [0.01, 0.01]", "hi = [-0.01, 0.01]", &["domain"]),
        ("hi = [0.01, 0.01]", "hi = [nan, 0.01]", &["domain"]),
        (
            "gravity = [0.0, -9.81]",
            "gravity = [0.0, nan]",
            &["gravity"],
        ),
        ("gravity = [0.0, -9.81]", "gravity = [0.0]", &["gravity"]),
        ("shape = \"segment\"", "shape = \"spline\"", &["spline"]),
        ("b = [0.01, 0.0]", "b = [0.0, 0.0]", &["wall"]),
        ("source = \"list\"", "source = \"cloud\"", &["cloud"]),
        (
            "name = \"floor\"",
            "name = \"quartz\"\nname = \"x\"",
            &["s.toml"],
        ),
        ("[run]\nduration = 1.0e-7", "", &["run"]),
        (
            "name = \"bad\"",
            "name = \"bad\"\nengine = \"lbm\"",
            &["engine", "lbm"],
        ),
        ("name = \"bad\"", "name = \"bad\"\nengine = 3", &["engine"]),
        ("name = \"bad\"", "name = \"bad\"\nfoo = 1", &["foo"]),
        (
            "duration = 1.0e-7",
            "duration = 1.0e-7\n[output]\nhistory = 0",
            &["history"],
        ),
        (
            "duration = 1.0e-7",
            "duration = 1.0e-7\n[output]\nsnapshots = [-1.0e-6]",
            &["snapshots"],
        ),
        (
            "duration = 1.0e-7",
            "duration = 1.0e-7\n[output]\nsnapshots = [1.0]",
            &["snapshots"],
        ),
        (
            "duration = 1.0e-7",
            "duration = 1.0e-7\n[output]\ncheckpoint_every = 0",
            &["checkpoint_every"],
        ),
        (
            "duration = 1.0e-7",
            "duration = 1.0e-7\n[[check]]\nkind = \"telepathy\"\nname = \"x\"",
            &["telepathy"],
        ),
    ];
    for (from, to, expect) in edits {
        all.push(run_edit(DEM, from, to, expect));
    }
    for (from, to, expect) in &edits[..12] {
        all.push(check_edit(DEM, from, to, expect));
    }
    all.push(check_edit(
        DEM,
        "at = [0.005, 0.0006]",
        "at = [0.005, 0.0002]",
        &["floor"],
    ));
}

fn all_cases() -> Vec<Case> {
    let mut all = Vec::new();
    names(&mut all);
    arguments(&mut all);
    dem_values(&mut all);
    dem3d::values(&mut all);
    others::engines(&mut all);
    others::pack(&mut all);
    all
}

/// Every bad input is refused as promised; prints how many were replayed.
#[test]
fn every_bad_input_is_refused_cleanly() {
    let all = all_cases();
    let failures: Vec<String> = all.iter().filter_map(replay).collect();
    eprintln!(
        "{} bad inputs replayed, {} not refused as promised",
        all.len(),
        failures.len()
    );
    assert!(
        failures.is_empty(),
        "{} of {}:\n{}",
        failures.len(),
        all.len(),
        failures.join("\n")
    );
}
