//! The FEM–DEM front end end to end: a bare charge passes its checks, a small coupled
//! ring runs and reports its figures, `grains check` prints F/B, and bad input is
//! refused with one line naming the key and value, exit 1 and no output directory.

mod common;
use common::*;

/// A 4 mm TNT charge on a coarse mesh: fast, and still within the checks' bounds.
const CHARGE: &str = r#"
engine = "fem_dem"
name = "t_charge"

[charge]
explosive = "tnt"
radius = 0.004

[charge.mesh]
size_edge = 0.1e-3
size_centre = 0.1e-3

[run]
duration = 1.2e-6

[output]
frames = 2
history = 50

[[check]]
kind = "energy_conservation"

# 40 elements across the radius: the burn ramp delays the front by ~5 % of r/D at a
# quarter radius (the example charge_only, 4× finer, holds 2 %).
[[check]]
kind = "detonation_arrival"
tolerance = 0.08
"#;

/// A 2 mm charge in a ring of 0.1 mm disks, 3 µs (shared with the library's tests).
const RING: &str = include_str!("../../sim/tests/data/ring_tiny.toml");

#[test]
fn bare_charge_conserves_energy_and_detonates_at_d_cj() {
    let (out, dir) = run_text(CHARGE, &[], &[]);
    assert_eq!(out.code, 0, "{}", out.stderr);
    let s = summary(dir.path());
    for c in s["checks"].as_array().unwrap() {
        assert_eq!(c["pass"], true, "{c}");
    }
    let speed = s["figures"]["detonation_front_speed"].as_f64().unwrap();
    assert!((speed / 6930.0 - 1.0).abs() < 0.03, "front speed {speed}");
    for f in [
        "history.csv",
        "frames/series.pvd",
        "frames/charge_00000.vtu",
        "plots/arrival.png",
        "plots/energies.png",
    ] {
        assert!(dir.path().join("out").join(f).exists(), "missing {f}");
    }
}

#[test]
fn small_ring_runs_coupled() {
    let (out, dir) = run_text(RING, &[], &[]);
    assert_eq!(out.code, 0, "{}", out.stderr);
    let s = summary(dir.path());
    let f = &s["figures"];
    let fb = f["fill_to_burster_ratio"].as_f64().unwrap();
    assert!(fb > 1.0 && fb < 1.3, "F/B {fb}");
    let v = f["mean_radial_velocity_terminal"].as_f64().unwrap();
    assert!(v > 200.0 && v < 2500.0, "velocity {v}");
    assert!(f.get("band_velocity_terminal").is_some());
    assert!(f["max_penetration_ratio"].as_f64().unwrap() < 0.5);
    let h = std::fs::read_to_string(dir.path().join("out/history.csv")).unwrap();
    let head = h.lines().next().unwrap();
    for col in [
        "inner_radius",
        "outer_radius",
        "pressure_front",
        "band_velocity",
        "spall_velocity",
        "band_fraction",
    ] {
        assert!(head.contains(col), "history lacks {col}");
    }
    for p in [
        "plots/radii.png",
        "plots/velocities.png",
        "plots/band_fraction.png",
        "frames/particles_00001.vtp",
    ] {
        assert!(dir.path().join("out").join(p).exists(), "missing {p}");
    }
    let snaps = std::fs::read_dir(dir.path().join("out/plots"))
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .starts_with("particles_")
        })
        .count();
    assert_eq!(snaps, 2, "snapshot at 2 µs and at the end");

    // `grains analyze` measures the frames by the run's own band rule: at every frame
    // that is also a history row (the start, the 2 µs snapshot, the end) it gives the
    // history's figures; a scenario naming a looser threshold puts more grains in the
    // band (this thin ring has none at φ ≥ 0.84 after the first microsecond).
    let run = dir.path().join("out");
    let ring = |extra: &str| {
        if !extra.is_empty() {
            let text = std::fs::read_to_string(run.join("scenario.toml")).unwrap();
            std::fs::write(run.join("scenario.toml"), format!("{text}\n{extra}")).unwrap();
        }
        let o = grains(&["analyze", run.to_str().unwrap(), "--json"]);
        assert_eq!(o.code, 0, "{}", o.stderr);
        let a: serde_json::Value = serde_json::from_str(&o.stdout).unwrap();
        a["ring"].clone()
    };
    let strict = ring("");
    assert_eq!(strict["rule"]["band_fraction"], 0.84, "{strict}");
    let cols: Vec<&str> = head.split(',').collect();
    let col = |k: &str| cols.iter().position(|c| *c == k).unwrap();
    let rows: Vec<Vec<f64>> = h
        .lines()
        .skip(1)
        .map(|l| {
            l.split(',')
                .map(|v| v.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    let frames = strict["frames"].as_array().unwrap();
    let mut matched = 0;
    for f in frames {
        let t = f["time"].as_f64().unwrap();
        let Some(r) = rows.iter().find(|r| r[col("time")] == t) else {
            continue;
        };
        matched += 1;
        for (k, c) in [
            ("band_fraction", "band_fraction"),
            ("band_velocity", "band_velocity"),
            ("mean_velocity", "mean_radial_velocity"),
        ] {
            // An empty band has no velocity: NaN in the history, null in the JSON.
            let (x, y) = (f[k].as_f64().unwrap_or(f64::NAN), r[col(c)]);
            assert!(
                (x.is_nan() && y.is_nan()) || (x - y).abs() <= 1e-9 * y.abs().max(1.0),
                "{k} at {t}: {x} vs {y}"
            );
        }
    }
    assert!(matched >= 2, "only {matched} frames at history rows");
    let loose = ring("[analysis]\nband_fraction = 0.5\n");
    assert_eq!(loose["rule"]["band_fraction"], 0.5);
    let fraction =
        |r: &serde_json::Value, k: usize| r["frames"][k]["band_fraction"].as_f64().unwrap();
    for k in 0..frames.len() {
        assert!(fraction(&loose, k) >= fraction(&strict, k), "frame {k}");
    }
    assert!((1..frames.len()).any(|k| fraction(&loose, k) > fraction(&strict, k)));
}

#[test]
fn check_reports_particles_and_fill_to_burster() {
    let v = check_json(RING);
    assert!(v["particles"].as_u64().unwrap() > 300);
    assert!(v["fill_to_burster_ratio"].as_f64().unwrap() > 1.0);
    assert_eq!(v["checks"][0]["pass"], true);
}

#[test]
fn unknown_explosive() {
    refused(
        &RING.replace("\"pe4\"", "\"semtex\""),
        &["charge.explosive", "semtex", "tnt"],
    );
}

#[test]
fn unknown_ring_material() {
    refused(
        &RING.replace(
            "material = \"quartz\"\ninner",
            "material = \"granite\"\ninner",
        ),
        &["ring.material", "granite"],
    );
}

#[test]
fn non_positive_eos_parameter() {
    let custom = CHARGE.replace(
        "explosive = \"tnt\"",
        "explosive = \"custom\"\n\n[charge.custom]\nname = \"x\"\ndensity = 1630.0\ndetonation_velocity = 6930.0\n\
         cj_pressure = 21.0e9\njwl = { a = 373.77e9, b = 3.747e9, r1 = -4.15, r2 = 0.9, omega = 0.35, e0 = 6.0e9 }\n\
         unreacted = { c0 = 2390.0, s = 2.05, gamma0 = 0.96 }\n\n[charge.extra]",
    )
    .replace("[charge.extra]\nradius", "radius");
    // Put radius back under [charge] (the custom table was inserted before it).
    let custom = custom.replacen("\nradius = 0.004\n", "\n", 1).replacen(
        "[charge]\n",
        "[charge]\nradius = 0.004\n",
        1,
    );
    refused(&custom, &["charge.custom.jwl.r1", "-4.15", "> 0"]);
}

#[test]
fn mesh_too_coarse() {
    refused(
        &CHARGE.replace("size_edge = 0.1e-3", "size_edge = 1.0e-3"),
        &["charge.mesh.size_edge", "too coarse"],
    );
}

#[test]
fn charge_overlapping_ring() {
    refused(
        &RING.replace("\nradius = 0.002\n", "\nradius = 0.0022\n"),
        &["charge.radius", "overlaps the ring"],
    );
}

#[test]
fn packing_that_does_not_fit_the_ring() {
    let text = RING.replace(
        "source = \"lattice\"\nd0 = 0.1e-3",
        "source = \"file\"\npath = \"pack.txt\"",
    );
    let pack = "# x y r\n0.0025 0.0 5e-5\n0.0 0.0031 5e-5\n";
    let (out, dir) = run_text(&text, &[("pack.txt", pack)], &[]);
    assert_refused(
        &out,
        dir.path(),
        &["ring.packing.path", "pack.txt", "does not fit the ring"],
    );
}

/// The xue-2019 examples that need no packing file (the charge alone and the lattice
/// rings) stay valid scenarios.
#[test]
fn self_contained_examples_validate() {
    let dir = example("xue2019");
    let mut seen = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if !(name.starts_with("ring_small") || name == "charge_only.toml") {
            continue;
        }
        let o = grains(&["check", path.to_str().unwrap(), "--json"]);
        assert_eq!(o.code, 0, "{name}: {}", o.stderr);
        seen += 1;
    }
    assert!(seen >= 6, "found only {seen} self-contained examples");
}

/// Elastic, frictionless grains keep all the work the charge does on them
/// (examples/xue2019/ring_small_elastic.toml, about 15 s in release):
/// `cargo test --release -p grains --test blast -- --ignored`.
#[test]
#[ignore]
fn elastic_ring_keeps_the_charges_work() {
    let file = example("xue2019/ring_small_elastic.toml");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = grains(&[
        "run",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let s = summary(dir.path());
    assert_eq!(s["checks"][0]["name"], "ring_energy_transfer_error");
    assert_eq!(s["checks"][0]["pass"], true, "{}", s["checks"][0]);
}

/// The tiny ring with `[analysis.dispersal]`: fields, maps, fronts, profiles, jets, the
/// models and the energy ledger are written; `grains analyze RUN_DIR` on its frames
/// gives the same figures at every frame (the frames carry each grain's mass and contact
/// stress); bad settings are refused with their key.
#[test]
fn dispersal_analysis_inline_and_from_the_frames() {
    let text = format!(
        "{RING}\n[analysis.dispersal]\ntimes = [2.0e-6]\nevery = 0.5e-6\n\
         [analysis.dispersal.band]\nmin_grains = 20\n"
    );
    let (out, dir) = run_text(&text, &[], &[]);
    assert_eq!(out.code, 0, "{}", out.stderr);
    let s = summary(dir.path());
    let f = &s["figures"];
    let d = &f["dispersal"];
    let frames = d["frames"].as_array().unwrap();
    // Frames at 0, 1.5, 2 and 3 µs, and samples every 0.5 µs besides.
    assert_eq!(frames.len(), 7);
    assert!(d["final"]["band_fraction"].as_f64().is_some(), "{d}");
    assert!(d["final"]["band_velocity"]["status"].is_string(), "{d}");
    assert!(
        d["fronts"].is_object() && d["jets"]["count"].is_u64(),
        "{d}"
    );
    assert!(frames
        .iter()
        .any(|r| r["pressure_front"].as_f64().is_some()));
    let m = &f["models"];
    let (gurney, lossless) = (
        m["classic_gurney"].as_f64().unwrap(),
        m["lossless_ceiling"]["velocity"].as_f64().unwrap(),
    );
    assert!(lossless > 0.0 && lossless < gurney, "{m}");
    assert_eq!(m["compaction"].as_array().unwrap().len(), 2);
    let milne = m["milne_porous_gurney"]["velocity"].as_f64().unwrap();
    assert!(milne > 0.0 && milne < gurney, "{m}");
    let l = &f["energy_ledger"];
    let work = l["work_on_ring"].as_f64().unwrap();
    for k in ["contact_damping", "contact_friction", "contact_stored"] {
        assert!(l[k].as_f64().unwrap() > 0.0, "{k}: {l}");
    }
    assert!(
        l["unaccounted"].as_f64().unwrap().abs() < 0.05 * work,
        "{l}"
    );
    let run = dir.path().join("out");
    for p in [
        "frames/fields.pvd",
        "frames/fields_00000.vts",
        "plots/dispersal/fronts.png",
        "plots/dispersal/radial_phi.png",
        "plots/dispersal/jets.png",
        "plots/dispersal/t_0002.00us/t_ring_shear_rate.png",
        "plots/dispersal/t_0002.00us/t_ring_pressure.png",
        "plots/dispersal/t_0002.00us/band_spectra.png",
        "plots/ring_energy.png",
    ] {
        assert!(run.join(p).exists(), "missing {p}");
    }
    let vtp = std::fs::read(run.join("frames/particles_00001.vtp")).unwrap();
    let head = String::from_utf8_lossy(&vtp[..vtp.len().min(4000)]);
    for a in ["Name=\"mass\"", "Name=\"stress\" NumberOfComponents=\"9\""] {
        assert!(head.contains(a), "{a}: {head}");
    }

    let o = grains(&["analyze", run.to_str().unwrap(), "--json"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let a: serde_json::Value = serde_json::from_str(&o.stdout).unwrap();
    let again = a["dispersal"]["frames"].as_array().unwrap();
    let with_files: Vec<&serde_json::Value> = frames
        .iter()
        .filter(|r| !r["fields_file"].is_null())
        .collect();
    assert_eq!(again.len(), with_files.len());
    for (x, y) in with_files.iter().zip(again) {
        for k in [
            "time",
            "r_in",
            "r_out",
            "pressure_front",
            "split",
            "shear_bands",
        ] {
            assert_eq!(x[k], y[k], "{k} at {}", x["time"]);
        }
    }
    assert!(run.join("analysis/analysis.json").exists());
    assert!(run.join("analysis/plots/dispersal/fronts.png").exists());
    let o = grains(&["analyze", run.to_str().unwrap(), "--times", "3e-6"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(run
        .join("analysis/plots/dispersal/t_0003.00us/t_ring_phi.png")
        .exists());

    let bad = format!("{RING}\n[analysis.dispersal]\ntimes = [5.0e-6]\n");
    let (out, dir) = run_text(&bad, &[], &[]);
    assert_refused(&out, dir.path(), &["analysis.dispersal.times[0]", "5e-6"]);
    let check = "\n[[check]]\nkind = \"shear_band_mode\"\nmode = 6\nfrom = 1e-6\nto = 2e-6\n";
    let (out, dir) = run_text(&format!("{RING}{check}at_least = 0.5\n"), &[], &[]);
    assert_refused(
        &out,
        dir.path(),
        &["shear_band_mode", "[analysis.dispersal]"],
    );
    let both = format!("{RING}\n[analysis.dispersal]\n{check}at_least = 0.5\nat_most = 0.9\n");
    let (out, dir) = run_text(&both, &[], &[]);
    assert_refused(&out, dir.path(), &["at_least/at_most", "exactly one"]);
    let count = "\n[[check]]\nkind = \"shear_band_count\"\nfrom = 1e-6\nto = 2e-6\n";
    let (out, dir) = run_text(&format!("{RING}{count}at_most = 7\n"), &[], &[]);
    assert_refused(
        &out,
        dir.path(),
        &["shear_band_count", "[analysis.dispersal]"],
    );
    let negative = format!("{RING}\n[analysis.dispersal]\n{count}at_least = -1\n");
    let (out, dir) = run_text(&negative, &[], &[]);
    assert_refused(&out, dir.path(), &["at_least/at_most", "-1"]);
}
