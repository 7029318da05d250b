//! `grains bench mpm`: one elastic block (or two stacked blocks in frictional contact)
//! of N points falling in a walled unit box on a G × G grid — the set-up of the taichi
//! mpm88 peer script (block [0.2, 0.6]², initial velocity (0, −1), g = 9.8,
//! Δt = 2·10⁻⁴ · 128/G), with an elastic solid instead of a fluid. Contact is as in a
//! scenario's default: Coulomb (μ = 0.3) with the separation test.

use crate::{fail, set_threads};
use glam::DVec2;
use grains_mpm::{
    step, Body, ContactLaw, ContactTable, Grid, Material, Motion, Particles, Setup, ShapeFunction,
    Solver, State, UpdateScheme,
};
use std::process::ExitCode;
use std::time::Instant;

/// Options of `grains bench mpm`.
pub struct Options {
    /// Points.
    pub particles: usize,
    /// Cells per side.
    pub grid: usize,
    /// Timed steps.
    pub steps: u64,
    /// Worker threads.
    pub threads: Option<usize>,
    /// 1 (one block) or 2 (two stacked blocks in contact).
    pub bodies: usize,
    /// Shape function name.
    pub shape: String,
    /// Update scheme name.
    pub update: String,
}

/// The benchmark set-up and its points.
pub fn setup(o: &Options) -> Result<(Setup, Particles), String> {
    let shape = match o.shape.as_str() {
        "linear" => ShapeFunction::Linear,
        "gimp" => ShapeFunction::Gimp,
        "bspline2" => ShapeFunction::Bspline2,
        s => return Err(format!("--shape = {s}: must be {}", ShapeFunction::NAMES)),
    };
    let scheme = match o.update.as_str() {
        "usf" => UpdateScheme::Usf,
        "usl" => UpdateScheme::Usl,
        "usavg" => UpdateScheme::Usavg,
        "musl" => UpdateScheme::Musl,
        s => return Err(format!("--update = {s}: must be {}", UpdateScheme::NAMES)),
    };
    if o.particles == 0 {
        return Err("--particles = 0: must be at least 1".into());
    }
    if !(8..=4096).contains(&o.grid) {
        return Err(format!(
            "--grid = {}: must be 8 to 4096 cells per side",
            o.grid
        ));
    }
    if !(1..=2).contains(&o.bodies) {
        return Err(format!("--bodies = {}: must be 1 or 2", o.bodies));
    }
    let h = 1.0 / o.grid as f64;
    let nx = (o.particles as f64).sqrt().ceil() as usize;
    let ny = o.particles.div_ceil(nx);
    let pitch = DVec2::new(0.4 / nx as f64, 0.4 / ny as f64);
    let vol = 0.16 / o.particles as f64;
    let mut p = Particles::default();
    for k in 0..o.particles {
        let (i, j) = (k % nx, k / nx);
        let x = DVec2::new(0.2, 0.2) + pitch * DVec2::new(i as f64 + 0.5, j as f64 + 0.5);
        let body = if o.bodies == 2 && 2 * j >= ny { 1 } else { 0 };
        p.push(body, vol, vol, x, DVec2::new(0.0, -1.0));
    }
    let material = Material::LinearElastic {
        name: "solid".into(),
        density: 1.0,
        bulk: 200.0,
        shear: 100.0,
        expansion: 0.0,
    };
    let bodies = (0..o.bodies)
        .map(|b| Body {
            name: format!("block{b}"),
            material: 0,
            motion: Motion::Free,
            temperature: None,
        })
        .collect();
    let s = Setup {
        grid: Grid {
            lo: DVec2::ZERO,
            h,
            cells: [o.grid, o.grid],
        },
        shape,
        half_width: (0.5 * pitch.max_element() / h).min(0.5),
        scheme,
        flip: 1.0,
        pass1_to_particles: true,
        materials: vec![material],
        bodies,
        contact: ContactTable::new(o.bodies, ContactLaw::Coulomb { mu: 0.3 }),
        // As scenarios do by default: bodies are corrected only where they touch.
        separation: Some(grains_mpm::contact::touching_separation(shape, 2) * 1.05 * h),
        walls: [Some(0.0); 4],
        gravity: DVec2::new(0.0, -9.8),
        dt: 2e-4 * 128.0 / o.grid as f64,
    };
    s.validate().map_err(|e| e.to_string())?;
    Ok((s, p))
}

/// FNV-1a over every point's position and velocity, in creation order.
pub fn state_hash(s: &State) -> u64 {
    let p = &s.particles;
    let mut order: Vec<usize> = (0..p.len()).collect();
    order.sort_unstable_by_key(|&i| p.id[i]);
    let mut h: u64 = 0xcbf29ce484222325;
    for &i in &order {
        for v in [p.pos[i].x, p.pos[i].y, p.vel[i].x, p.vel[i].y] {
            for b in v.to_bits().to_le_bytes() {
                h ^= b as u64;
                h = h.wrapping_mul(0x100000001b3);
            }
        }
    }
    h
}

/// Runs the benchmark.
pub fn run(o: Options) -> ExitCode {
    let (setup, p) = match setup(&o) {
        Ok(v) => v,
        Err(e) => return fail(1, &e),
    };
    let threads = match set_threads(o.threads) {
        Ok(t) => t,
        Err(e) => return fail(1, &e),
    };
    let mut state = State {
        particles: p,
        ..Default::default()
    };
    let mut solver = Solver::new(&setup, &mut state);
    // Warm-up, as the peer script does before timing (it compiles its kernels there).
    for _ in 0..50 {
        if let Err(e) = step(&setup, &mut state, &mut solver) {
            return fail(3, &e.to_string());
        }
    }
    let c0 = crate::bench::cpu_seconds();
    let t0 = Instant::now();
    // Step from inside the pool, so parallel stages start on a worker thread.
    let r = rayon::scope(|_| {
        for _ in 0..o.steps {
            step(&setup, &mut state, &mut solver)?;
        }
        Ok::<(), grains_mpm::Unstable>(())
    });
    if let Err(e) = r {
        return fail(3, &e.to_string());
    }
    let secs = t0.elapsed().as_secs_f64();
    let cpu = c0.and_then(|c0| Some(crate::bench::cpu_seconds()? - c0));
    let rate = o.particles as f64 * o.steps as f64 / secs;
    println!("particles: {}", o.particles);
    println!("grid: {0}x{0}", o.grid);
    println!("bodies: {}", o.bodies);
    println!("shape: {}, update: {}", o.shape, o.update);
    println!(
        "steps: {} (after 50 warm-up steps), dt = {:.3e} s",
        o.steps, setup.dt
    );
    println!("threads: {threads}");
    println!("wall time: {secs:.3} s");
    if let Some(cpu) = cpu {
        println!("cpu time: {cpu:.3} s");
        println!(
            "particle-steps per cpu-s: {:.4e}",
            o.particles as f64 * o.steps as f64 / cpu
        );
    }
    println!("state-hash: {:016x}", state_hash(&state));
    println!("particle-steps/s: {rate:.4e}");
    ExitCode::SUCCESS
}
