//! Speed of the dispersal analysis on one frame of a synthetic ring the size of
//! xue-2019 test 2 (R = 10–30 mm, d0 = 95.7 µm: about 0.32 M grains, 0.95 M contacts).
//!
//! Run: `cargo run --release -p grains-analysis --example dispersal_bench`
//! (`RAYON_NUM_THREADS=1` for one core). Prints the time of each stage, best of 3.

use glam::DVec2;
use grains_analysis::dispersal::synthetic::LatticeRing;
use grains_analysis::dispersal::{
    analyze_frame, fields_grid, jets, write_maps, Contacts, DispersalSpec, ParticleSet,
    StressSource,
};
use std::time::Instant;

fn best_of<T>(n: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut out = None;
    for _ in 0..n {
        let t = Instant::now();
        let v = f();
        best = best.min(t.elapsed().as_secs_f64());
        out = Some(v);
    }
    (best, out.unwrap())
}

fn main() {
    let d0 = 95.7e-6;
    let t = Instant::now();
    let ring = LatticeRing::new(DVec2::ZERO, 10e-3, 30e-3, d0, 0.99 * d0, 0.2, 0.03, 1);
    // An expanding ring with a shocked inner half: v_r = 300 m/s + a ripple.
    let vel: Vec<DVec2> = ring
        .pos
        .iter()
        .map(|x| (300.0 + 20.0 * (6.0 * x.y.atan2(x.x)).cos()) * x.normalize())
        .collect();
    let (i, j, mut f) = ring.pressure_contacts(200e6);
    for k in 0..i.len() {
        if ring.pos[i[k] as usize].length() > 20e-3 {
            f[k] = DVec2::ZERO;
        }
    }
    println!(
        "synthetic ring: {} grains, {} contacts, built in {:.2} s; rayon threads {}",
        ring.pos.len(),
        i.len(),
        t.elapsed().as_secs_f64(),
        rayon::current_num_threads()
    );
    let set = ParticleSet::new(&ring.pos, &vel, &ring.radius, &ring.mass, &ring.id).unwrap();
    let c = Contacts::new(&i, &j, &f, set.len()).unwrap();
    // What runs and frames carry: each grain's Σ a ⊗ f, half the branch as each arm.
    let mut moments = vec![glam::DMat2::ZERO; set.len()];
    for k in 0..i.len() {
        let (a, b) = (i[k] as usize, j[k] as usize);
        let half = 0.5 * (ring.pos[b] - ring.pos[a]);
        let m = glam::DMat2::from_cols(half * f[k].x, half * f[k].y);
        moments[a] += m;
        moments[b] += m;
    }
    let spec = DispersalSpec::default();
    let plain = DispersalSpec {
        kernel_width: 0.0,
        ..spec
    };
    let mut last = None;
    for (name, s, source) in [
        ("plain bins, contacts", plain, StressSource::Contacts(c)),
        (
            "hat kernel w = d0 (default), contacts",
            spec,
            StressSource::Contacts(c),
        ),
        (
            "hat kernel w = d0, per-grain stress (as runs and frames give it)",
            spec,
            StressSource::Particles(&moments),
        ),
    ] {
        let (secs, a) = best_of(3, || {
            analyze_frame(&s, DVec2::ZERO, d0, 10e-6, &set, Some(source)).unwrap()
        });
        println!(
            "analyze_frame, {name} (fields + stress, band split, fronts, profiles, shear bands): \
             {secs:.3} s [{} rings x {} sectors]",
            a.fields.grid.n_r(),
            a.fields.grid.n_theta()
        );
        last = Some(a);
    }
    let a = last.unwrap();
    let (secs, found) = best_of(3, || jets(DVec2::ZERO, &set, d0, &spec.jets));
    println!("jets: {secs:.3} s ({} spikes)", found.jets.len());
    let dir = std::env::temp_dir().join("grains-dispersal-bench");
    std::fs::create_dir_all(&dir).unwrap();
    let (secs, _) = best_of(3, || {
        fields_grid(&a.fields)
            .write(&dir.join("fields.vts"))
            .unwrap()
    });
    println!("fields .vts: {secs:.3} s");
    let (secs, maps) = best_of(1, || {
        write_maps(&dir, "bench", &a.fields, a.time, Some(10e-3), &a.overlays()).unwrap()
    });
    println!(
        "{} polar maps: {secs:.3} s (in {})",
        maps.len(),
        dir.display()
    );
    println!("summary: {:?}", a.summary());
}
