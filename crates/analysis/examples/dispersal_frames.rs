//! Runs the dispersal analysis on the particle frames of a finished ring run, as a
//! stand-in for `grains analyze RUN_DIR` until the CLI wires it: every frame's polar
//! maps and `.vts`, the R–t diagram, radial profiles, the band's azimuthal profiles,
//! the jets of the last frame traced back to the middle one, and one summary line per
//! frame. The frames carry no contact forces yet, so there is no stress or R_p.
//!
//! Run: `cargo run --release -p grains-analysis --example dispersal_frames -- RUN_DIR
//! [grain density, default 2560] [sectors, default 180]`; output in RUN_DIR/dispersal/.

use glam::DVec2;
use grains_analysis::dispersal::{
    analyze_frame, fields_grid, front_history, jets, plot_azimuthal, plot_fronts,
    plot_radial_profiles, trace_jets, write_maps, DispersalSpec, ParticleSet,
};
use grains_core::pvd::PvdSeries;
use grains_core::vtk::{find_array, read_appended_arrays};
use std::path::{Path, PathBuf};

struct Frame {
    time: f64,
    pos: Vec<DVec2>,
    vel: Vec<DVec2>,
    radius: Vec<f64>,
    mass: Vec<f64>,
    id: Vec<u32>,
}

fn load(path: &Path, time: f64, density: f64) -> Frame {
    let a = read_appended_arrays(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let get = |s: &str, n: &str| {
        find_array(&a, s, n)
            .unwrap_or_else(|| panic!("{}: no {s}/{n}", path.display()))
            .values
            .clone()
    };
    let pts = get("Points", "Points");
    let v = get("PointData", "velocity");
    let radius = get("PointData", "radius");
    let id = get("PointData", "id");
    Frame {
        time,
        pos: pts.chunks(3).map(|c| DVec2::new(c[0], c[1])).collect(),
        vel: v.chunks(3).map(|c| DVec2::new(c[0], c[1])).collect(),
        mass: radius
            .iter()
            .map(|r| density * std::f64::consts::PI * r * r)
            .collect(),
        id: id.iter().map(|&x| x as u32).collect(),
        radius,
    }
}

fn set(f: &Frame) -> ParticleSet<'_> {
    ParticleSet::new(&f.pos, &f.vel, &f.radius, &f.mass, &f.id).unwrap()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let run = PathBuf::from(
        args.get(1)
            .expect("usage: dispersal_frames RUN_DIR [density]"),
    );
    let density: f64 = args.get(2).map_or(2560.0, |s| s.parse().expect("density"));
    let series = PvdSeries::load(&run.join("frames/series.pvd")).expect("frames/series.pvd");
    let frames: Vec<Frame> = series
        .entries()
        .iter()
        .filter(|e| e.file.contains("particles"))
        .map(|e| load(&run.join("frames").join(&e.file), e.time, density))
        .collect();
    let out = run.join("dispersal");
    std::fs::create_dir_all(&out).unwrap();
    let sectors: usize = args.get(3).map_or(180, |s| s.parse().expect("sectors"));
    let spec = DispersalSpec {
        sectors,
        ..DispersalSpec::default()
    };
    let d0 = 2.0 * frames[0].radius.iter().sum::<f64>() / frames[0].radius.len() as f64;
    let mut fronts = Vec::new();
    let mut profiles = Vec::new();
    let mut layers_mid = None;
    for (k, f) in frames.iter().enumerate() {
        let t0 = std::time::Instant::now();
        let a = analyze_frame(&spec, DVec2::ZERO, d0, f.time, &set(f), None).unwrap();
        let secs = t0.elapsed().as_secs_f64();
        let stem = format!("frame_{k:03}");
        fields_grid(&a.fields)
            .write(&out.join(format!("{stem}.vts")))
            .unwrap();
        write_maps(
            &out,
            &stem,
            &a.fields,
            f.time,
            // The charge fills the ring's inner radius (the frames do not carry it).
            Some(a.fronts.r_in),
            &a.overlays(),
        )
        .unwrap();
        plot_azimuthal(&out, &format!("{stem}_band"), f.time, &a.azimuthal).unwrap();
        let s = a.summary();
        println!(
            "t = {:6.2} µs ({secs:.2} s): R_in {:.2} R_out {:.2} R_comp {:?} band {:.3} v {:?} spall {:.3} v {:?} modes {:?} shear {:?}",
            f.time * 1e6,
            s.r_in * 1e3,
            s.r_out * 1e3,
            s.split.band_outer_radius.map(|r| r * 1e3),
            s.split.band.number_fraction,
            s.split.band.velocity.number_weighted(),
            s.split.spall.number_fraction,
            s.split.spall.velocity.number_weighted(),
            s.band_modes,
            s.shear_bands
        );
        if k == frames.len() / 2 {
            layers_mid = Some(grains_analysis::dispersal::bands::classify(
                &a.fields,
                &a.band_map,
                &spec.band,
            ));
        }
        fronts.push(a.fronts.clone());
        profiles.push((f.time, a.radial.clone()));
    }
    let h = front_history(fronts, spec.radial_bin * d0);
    plot_fronts(&out.join("fronts.png"), "ring fronts", &h).unwrap();
    let pick: Vec<(f64, &grains_analysis::dispersal::RadialProfile)> = profiles
        .iter()
        .step_by((profiles.len() / 4).max(1))
        .map(|(t, p)| (*t, p))
        .collect();
    plot_radial_profiles(&out, "radial", &pick).unwrap();
    let last = frames.last().unwrap();
    let j = jets(DVec2::ZERO, &set(last), d0, &spec.jets);
    let mid = &frames[frames.len() / 2];
    let origins = trace_jets(&j, DVec2::ZERO, &set(mid), layers_mid.as_deref());
    println!(
        "jets at {:.1} µs: {} (threshold {:.2} mm); traced to {:.1} µs:",
        last.time * 1e6,
        j.jets.len(),
        j.threshold * 1e3,
        mid.time * 1e6
    );
    for (jet, o) in j.jets.iter().zip(&origins) {
        println!(
            "  θ {:6.1}° height {:.2} mm, {} grains <- θ {:6.1}° r {:.2} mm, spread {:.1}°, layers {:?}",
            jet.theta.to_degrees(),
            jet.height * 1e3,
            jet.grains.len(),
            o.theta.to_degrees(),
            o.radius * 1e3,
            o.angular_spread.to_degrees(),
            o.layers
        );
    }
}
