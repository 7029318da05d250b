//! `grains pack` and `grains analyze` end to end: bad specs are refused with nothing
//! written, a small packing writes every output, is the same on 1 and 2 threads, and
//! reads back through `grains analyze` and a DEM scenario.

mod common;
use common::*;
use std::path::Path;

const SPEC: &str = r#"
name = "tiny"
seed = 3

[domain]
shape = "rectangle"
width = 0.02
height = 0.02
periodic_x = true

[sizes]
distribution = "gaussian"
d0 = 1.0e-3
delta = 0.113

[protocol]
rate = 2e-3
target_fraction = 0.8

[[check]]
figure = "packing_fraction_bulk"
at_least = 0.8
"#;

fn grains_at(dir: &Path, args: &[&str]) -> (i32, String, String) {
    let o = grains_in(Some(dir), args);
    (o.code, o.stdout, o.stderr)
}

fn pack(dir: &Path, text: &str, threads: &str) -> (i32, String) {
    std::fs::write(dir.join("spec.toml"), text).unwrap();
    let (code, _, err) = grains_at(
        dir,
        &["pack", "spec.toml", "--out", "out", "--threads", threads],
    );
    (code, err)
}

/// Packs `text` in a scratch directory and asserts that it is refused
/// ([`assert_refused`]), `expect` in what is printed.
fn pack_refused(text: &str, expect: &str) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("spec.toml"), text).unwrap();
    let args = ["pack", "spec.toml", "--out", "out", "--threads", "1"];
    let out = grains_in(Some(dir.path()), &args);
    assert_refused(&out, dir.path(), &[]);
    assert!(out.stderr.contains(expect), "{expect}: {}", out.stderr);
}

#[test]
fn bad_specs_are_refused_without_output() {
    let cases = [
        ("delta = 0.113", "delta = 0.9", "sizes.delta = 0.9"),
        ("d0 = 1.0e-3", "d0 = -1.0e-3", "sizes.d0 = -0.001"),
        (
            "target_fraction = 0.8",
            "target_fraction = 0.95",
            "protocol.target_fraction = 0.95",
        ),
        ("width = 0.02", "width = 0.001", "domain.width = 0.001"),
        ("rate = 2e-3", "rate = 0.0", "protocol.rate = 0"),
        (
            "rate = 2e-3",
            "rate = 2e-3\nstart = \"grid\"",
            "expected `lattice` or `deposit`",
        ),
        (
            "figure = \"packing_fraction_bulk\"",
            "figure = \"nope\"",
            "check[0].figure",
        ),
        ("seed = 3", "seed = 3\nbogus = 1", "bogus"),
        (
            "rate = 2e-3",
            "rate = 2e-3\nanneal_sweeps = 20000000",
            "protocol.anneal_sweeps = 20000000",
        ),
        (
            "rate = 2e-3",
            "rate = 2e-3\nsort_sweeps = 10\nstart = \"deposit\"",
            "protocol.sort_sweeps = 10",
        ),
        (
            "rate = 2e-3",
            "rate = 2e-3\nstart_fraction = 0.85",
            "protocol.start_fraction = 0.85",
        ),
    ];
    for (from, to, expect) in cases {
        pack_refused(&SPEC.replace(from, to), expect);
    }
    let annulus = SPEC.replace(
        "shape = \"rectangle\"\nwidth = 0.02\nheight = 0.02\nperiodic_x = true",
        "shape = \"annulus\"\nr_in = 0.01\nr_out = 0.009",
    );
    pack_refused(&annulus, "domain.r_out = 0.009");
}

/// Packs `spec` into `dir/out` on 1 thread and into a scratch directory on 2, asserts the
/// two packing files are identical, and returns the file.
fn packed_on_one_and_two_threads(dir: &Path, spec: &str, what: &str) -> String {
    let two = tempfile::tempdir().unwrap();
    let (code, err) = pack(dir, spec, "1");
    assert_eq!(code, 0, "{what}: {err}");
    let (code, err) = pack(two.path(), spec, "2");
    assert_eq!(code, 0, "{what}: {err}");
    let a = std::fs::read_to_string(dir.join("out/packing.txt")).unwrap();
    let b = std::fs::read_to_string(two.path().join("out/packing.txt")).unwrap();
    assert!(a == b, "{what} differs between 1 and 2 threads");
    a
}

#[test]
fn small_packing_writes_everything_and_is_thread_independent() {
    let one = tempfile::tempdir().unwrap();
    let a = packed_on_one_and_two_threads(one.path(), SPEC, "packing");
    // The deposition start too.
    let deposit = SPEC.replace("rate = 2e-3", "rate = 2e-3\nstart = \"deposit\"");
    let c =
        packed_on_one_and_two_threads(tempfile::tempdir().unwrap().path(), &deposit, "deposition");
    assert!(c != a, "the start makes no difference");
    // And an anneal before the growth.
    let anneal = SPEC.replace("rate = 2e-3", "rate = 2e-3\nanneal_sweeps = 40");
    let e = packed_on_one_and_two_threads(tempfile::tempdir().unwrap().path(), &anneal, "annealed");
    assert!(e != a, "the anneal makes no difference");
    // And sizes sorted on the lattice before a dense start.
    let sorted = SPEC.replace(
        "rate = 2e-3",
        "rate = 2e-3\nstart_fraction = 0.84\nsort_sweeps = 5",
    );
    let g = packed_on_one_and_two_threads(tempfile::tempdir().unwrap().path(), &sorted, "sorted");
    assert!(
        g.contains("sort_sweeps = 5"),
        "the protocol line names the sort"
    );
    assert!(a.starts_with("# content_key = "));
    assert!(a.lines().nth(1).unwrap().starts_with("# grains pack: tiny"));
    assert!(a.contains("# spec_key = "));
    assert!(a.contains("# domain = rectangle"));
    for f in [
        "summary.json",
        "spec.toml",
        "frames/packing.vtp",
        "plots/psi6_map.png",
        "plots/psi6_cdf.png",
        "plots/size_pdf.png",
        "plots/size_cdf.png",
        "plots/rose.png",
    ] {
        assert!(one.path().join("out").join(f).exists(), "missing {f}");
    }
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(one.path().join("out/summary.json")).unwrap(),
    )
    .unwrap();
    for k in grains_sim::analyze::MAIN_FIGURES
        .iter()
        .chain(&["wall_time_s"])
    {
        assert!(summary[k].is_number(), "summary.json {k}: {}", summary[k]);
    }
    let d0 = summary["mean_diameter"].as_f64().unwrap();
    assert!((d0 / 1e-3 - 1.0).abs() < 0.06, "d0 {d0}");
    assert!(summary["packing_fraction_bulk"].as_f64().unwrap() >= 0.8);

    // The packing file reads back through analyze with the same figures.
    let (code, out, err) = grains_at(
        one.path(),
        &["analyze", "out/packing.txt", "--out", "an", "--json"],
    );
    assert_eq!(code, 0, "{err}");
    let again: serde_json::Value = serde_json::from_str(&out).unwrap();
    for k in [
        "particles",
        "psi6_local_mean_interior",
        "psi6_global_interior",
        "mean_coordination",
        "packing_fraction_bulk",
    ] {
        let (x, y) = (again[k].as_f64().unwrap(), summary[k].as_f64().unwrap());
        assert!((x - y).abs() <= 1e-9 * y.abs().max(1.0), "{k}: {x} vs {y}");
    }
    let (code, _, err) = grains_at(
        one.path(),
        &["analyze", "out/frames/packing.vtp", "--out", "an2"],
    );
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = grains_at(one.path(), &["analyze", "missing.txt"]);
    assert_eq!(code, 1, "{err}");
}

/// `grains pack` with `dim = 3`: jammed spheres in a cylinder with their fraction,
/// coordination and fabric reported; bad values refused with nothing written; the
/// packing file loaded by a 3D scenario (`source = "file"`), which runs.
#[test]
fn spheres_pack_and_start_a_3d_run() {
    let spec = "name = \"balls\"\ndim = 3\nseed = 2\n[domain]\nshape = \"cylinder\"\nradius = 1.0\nheight = 2.0\n[sizes]\ncount = 60\ndiameter = 0.002\n";
    let dir = tempfile::tempdir().unwrap();
    for (from, to, key) in [
        ("count = 60", "count = 1", "sizes.count"),
        ("diameter = 0.002", "diameter = 0.0", "sizes.diameter"),
        ("height = 2.0", "height = -2.0", "domain.height"),
        ("dim = 3", "dim = 4", "dim"),
    ] {
        pack_refused(&spec.replace(from, to), key);
    }
    let (code, err) = pack(dir.path(), spec, "1");
    assert_eq!(code, 0, "{err}");
    let s: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("out/summary.json")).unwrap(),
    )
    .unwrap();
    let f = &s["figures"];
    let fabric: Vec<f64> = f["fabric_eigenvalues"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert!(
        (fabric.iter().sum::<f64>() - 1.0).abs() < 1e-9,
        "{fabric:?}"
    );
    let phi = f["packing_fraction_bulk"].as_f64().unwrap();
    assert!((0.4..0.7).contains(&phi), "{s}");
    assert!(f["mean_coordination"].as_f64().unwrap() > 4.0, "{s}");
    // The frame and the plots: the spheres from the side and from above, and the
    // distribution of contacts per sphere beside its data.
    let out = dir.path().join("out");
    for file in [
        "plots/packing_side.png",
        "plots/packing_top.png",
        "plots/contacts.png",
    ] {
        assert!(out.join(file).is_file(), "{file} missing");
    }
    let vtp = std::fs::read(out.join("frames/packing.vtp")).unwrap();
    let vtp = String::from_utf8_lossy(&vtp);
    assert!(vtp.contains("NumberOfPoints=\"60\""), "{vtp}");
    for array in ["radius", "contacts", "rattler", "interior"] {
        assert!(vtp.contains(&format!("Name=\"{array}\"")), "{array}");
    }
    let csv = std::fs::read_to_string(out.join("plots/contacts.csv")).unwrap();
    let all: f64 = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().parse::<f64>().unwrap())
        .sum();
    assert!((all - 1.0).abs() < 1e-12, "{csv}");
    let scenario = r#"engine = "dem"
dim = 3
name = "from_packing"
gravity = [0.0, 0.0, -9.81]

[domain]
lo = [-0.02, -0.02, -0.001]
hi = [0.02, 0.02, 0.03]

[[material]]
name = "grain"
density = 2500.0
youngs = 1.0e7
poisson = 0.3
restitution = 0.5
friction = 0.5

[contact]
model = "granular"
normal = "hertz/material"
damping = "restitution"
tangential = "mindlin"

[[particles]]
source = "file"
material = "grain"
path = "out/packing.txt"

[[wall]]
shape = "plane"
name = "floor"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]

[run]
duration = 1.0e-3
"#;
    std::fs::write(dir.path().join("run.toml"), scenario).unwrap();
    let (code, _, err) = grains_at(dir.path(), &["run", "run.toml", "--out", "run"]);
    assert_eq!(code, 0, "{err}");
    let r: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("run/summary.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(r["particles"], 60, "{r}");
    // A 2D packing line (x y r) is refused by the 3D reader.
    std::fs::write(dir.path().join("flat.txt"), "0.0 0.0 0.001\n").unwrap();
    let bad = scenario.replace("out/packing.txt", "flat.txt");
    std::fs::write(dir.path().join("bad.toml"), bad).unwrap();
    let (code, _, err) = grains_at(dir.path(), &["run", "bad.toml", "--out", "bad"]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("particles[0].path") && err.contains("x y z r"),
        "{err}"
    );
    assert!(!dir.path().join("bad").exists());
    // The example spec passes its checks.
    let (code, _, err) = grains_at(
        dir.path(),
        &[
            "pack",
            example("dem3d/pack_spheres.toml").to_str().unwrap(),
            "--out",
            "example",
        ],
    );
    assert_eq!(code, 0, "{err}");
}
