//! The dispersal analysis on a DEM run: a ring of disks pushed outward, analysed inline
//! about the centre of its `[dispersal]` table and again from its frames.

mod common;
use common::*;
use std::fmt::Write as _;

/// A ring of about 4,000 disks (r = 0.1 mm, 5–9 mm) moving outward at 20 m/s × (5 mm/r)²:
/// the inner ones are faster, so they catch up with the outer ones; 10 µs.
fn ring_scenario(dispersal: &str) -> String {
    let mut s = String::from(
        r#"name = "dem_ring"
[domain]
lo = [-0.02, -0.02]
hi = [0.02, 0.02]

[[material]]
name = "quartz"
density = 2560.0
youngs = 72.0e9
poisson = 0.27
restitution = 0.5
friction = 0.3

[run]
duration = 10.0e-6

[output]
frames = 4
history = 40

[[particles]]
source = "list"
material = "quartz"
disks = [
"#,
    );
    let (r, gap) = (1.0e-4, 2.05e-4);
    let mut ring = 5.0e-3;
    while ring < 9.0e-3 {
        let n = (std::f64::consts::TAU * ring / gap) as usize;
        for k in 0..n {
            let a = std::f64::consts::TAU * (k as f64 + 0.5 * (n % 2) as f64) / n as f64;
            let speed = 20.0 * (5.0e-3 / ring).powi(2);
            let _ = writeln!(
                s,
                "  {{ at = [{:e}, {:e}], radius = {r:e}, velocity = [{:e}, {:e}] }},",
                ring * a.cos(),
                ring * a.sin(),
                speed * a.cos(),
                speed * a.sin()
            );
        }
        ring += gap;
    }
    s.push_str("]\n");
    s.push_str(dispersal);
    s
}

#[test]
fn a_dem_ring_is_analysed_inline_and_from_its_frames() {
    let text = ring_scenario(
        "\n[dispersal]\ncentre = [0.0, 0.0]\ntimes = [5.0e-6]\nsectors = 90\n\
         [dispersal.band]\nmin_grains = 10\n",
    );
    let (out, dir) = run_text(&text, &[], &[]);
    assert_eq!(out.code, 0, "{}", out.stderr);
    let s = summary(dir.path());
    let d = &s["figures"]["dispersal"];
    let frames = d["frames"].as_array().unwrap();
    // Frames at 0, 2.5, 5 (also the chosen time), 7.5 and 10 µs.
    assert_eq!(frames.len(), 5, "{d}");
    assert!(frames
        .iter()
        .all(|r| r["pressure_front"].as_f64().is_some()));
    let r_out = frames.last().unwrap()["r_out"].as_f64().unwrap();
    assert!(r_out > 9.0e-3, "the ring spread: {r_out}");
    let run = dir.path().join("out");
    assert!(run
        .join("plots/dispersal/t_0005.00us/dem_ring_shear_rate.png")
        .exists());
    assert!(run.join("frames/fields.pvd").exists());

    let o = grains(&["analyze", run.to_str().unwrap(), "--json"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let a: serde_json::Value = serde_json::from_str(&o.stdout).unwrap();
    let again = a["dispersal"]["frames"].as_array().unwrap();
    assert_eq!(again.len(), frames.len());
    for (x, y) in frames.iter().zip(again) {
        assert_eq!(x["split"], y["split"], "at {}", x["time"]);
        assert_eq!(x["pressure_front"], y["pressure_front"]);
    }
    assert!(a.get("models").is_none(), "no charge, no models");

    // A DEM run is analysed about a centre it must give.
    let (out, dir) = run_text(&ring_scenario("\n[dispersal]\n"), &[], &[]);
    assert_refused(&out, dir.path(), &["dispersal.centre"]);
}
