//! `grains bench mpm`: one block (or two stacked blocks in frictional contact) of N
//! points falling in a walled unit box on a G × G grid — the set-up of the taichi mpm88
//! peer script (block [0.2, 0.6]², initial velocity (0, −1), g = 9.8,
//! Δt = 2·10⁻⁴ · 128/G), with a solid instead of a fluid. Contact is as in a scenario's
//! default: Coulomb (μ = 0.3) with the separation test. The solid is elastic by default;
//! `--material` times the models with memory against it, all with K = 200 and an
//! instantaneous G = 100, so the time step is the same:
//!
//! * `thermal`: elastic, α = 10⁻⁴, heated at 100 per second;
//! * `neo_hookean`;
//! * `j2`: σ_y = 5, H = 10 (the block yields once it lands, after ~1000 steps at G = 128);
//! * `maxwell`: G∞ = 50 and two Prony terms, 30 and 20 with τ = 0.01 and 0.1 s;
//! * `maxwell3`: G∞ = 40, three terms of 20 (τ = 0.001, 0.01, 0.1 s);
//! * `maxwell4`: G∞ = 40, four terms of 15 (τ = 0.001 to 1 s).

use super::{cpu_seconds, Report};
use glam::DVec2;
use grains_mpm::{
    step, Body, ContactLaw, ContactTable, Grid, Material, Motion, Particles, PronyTerm, Setup,
    ShapeFunction, Solver, State, TemperatureHistory, UpdateScheme,
};
use std::time::Instant;

/// Options of `grains bench mpm`.
pub struct Options {
    /// Points.
    pub particles: usize,
    /// Cells per side.
    pub grid: usize,
    /// Timed steps.
    pub steps: u64,
    /// 1 (one block) or 2 (two stacked blocks in contact).
    pub bodies: usize,
    /// Shape function name.
    pub shape: String,
    /// Update scheme name.
    pub update: String,
    /// The block's material (see the module's list).
    pub material: String,
}

/// The materials `--material` names, with the temperature history of `thermal`.
pub const MATERIALS: &str = "elastic, thermal, neo_hookean, j2, maxwell, maxwell3 or maxwell4";

/// The block's material and temperature history.
fn material(name: &str) -> Result<(Material, Option<TemperatureHistory>), String> {
    let (density, bulk, shear) = (1.0, 200.0, 100.0);
    let elastic = |expansion| Material::LinearElastic {
        name: name.into(),
        density,
        bulk,
        shear,
        expansion,
    };
    let maxwell = |relaxed: f64, terms: &[(f64, f64)]| Material::Maxwell {
        name: name.into(),
        density,
        bulk,
        shear: relaxed,
        prony: terms
            .iter()
            .map(|&(shear, time)| PronyTerm { shear, time })
            .collect(),
        expansion: 0.0,
    };
    Ok(match name {
        "elastic" => (elastic(0.0), None),
        "thermal" => (
            elastic(1e-4),
            Some(TemperatureHistory::Rate {
                initial: 0.0,
                rate: 100.0,
            }),
        ),
        "neo_hookean" => (
            Material::NeoHookean {
                name: name.into(),
                density,
                bulk,
                shear,
            },
            None,
        ),
        "j2" => (
            Material::J2Plastic {
                name: name.into(),
                density,
                bulk,
                shear,
                yield_stress: 5.0,
                hardening: 10.0,
                expansion: 0.0,
            },
            None,
        ),
        "maxwell" => (maxwell(50.0, &[(30.0, 0.01), (20.0, 0.1)]), None),
        "maxwell3" => (
            maxwell(40.0, &[(20.0, 0.001), (20.0, 0.01), (20.0, 0.1)]),
            None,
        ),
        "maxwell4" => (
            maxwell(
                40.0,
                &[(15.0, 0.001), (15.0, 0.01), (15.0, 0.1), (15.0, 1.0)],
            ),
            None,
        ),
        m => return Err(format!("--material = {m}: must be {MATERIALS}")),
    })
}

/// The benchmark set-up, its points and its step.
pub fn setup(o: &Options) -> Result<(Setup, Particles, f64), String> {
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
    if o.steps == 0 {
        return Err("--steps = 0: must be at least 1 (a rate needs timed steps)".into());
    }
    if !(8..=4096).contains(&o.grid) {
        return Err(format!(
            "--grid = {}: must be 8 to 4096 cells per side",
            o.grid
        ));
    }
    let nodes = ((o.grid + 1) * (o.grid + 1)) as u64;
    crate::estimate::Estimate::new(
        o.particles as u64,
        o.steps,
        o.particles as u64 * 170 + nodes * 176,
        crate::estimate::rate::MPM,
        1,
    )
    .fits_memory("--particles")?;
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
    let (material, temperature) = material(&o.material)?;
    let bodies = (0..o.bodies)
        .map(|b| Body {
            name: format!("block{b}"),
            material: 0,
            motion: Motion::Free,
            temperature: temperature.clone(),
        })
        .collect();
    let s = Setup {
        grid: Grid {
            lo: DVec2::ZERO,
            h,
            cells: [o.grid, o.grid],
            periodic_y: false,
        },
        shape,
        half_width: (0.5 * pitch.max_element() / h).min(0.5),
        scheme,
        flip: 1.0,
        pass1_to_particles: true,
        materials: vec![material],
        bodies,
        contact: ContactTable::new(o.bodies, ContactLaw::Coulomb { mu: 0.3 }),
        crowd: Default::default(),
        // As scenarios do by default: bodies are corrected only where they touch.
        separation: Some(grains_mpm::contact::touching_separation(shape, 2) * 1.05 * h),
        walls: [Some(0.0); 4],
        gravity: DVec2::new(0.0, -9.8),
        ledger: false,
    };
    s.validate().map_err(|e| e.to_string())?;
    Ok((s, p, 2e-4 * 128.0 / o.grid as f64))
}

/// Runs the benchmark on the current thread pool.
pub fn run(o: &Options) -> Result<Report, String> {
    let (setup, p, dt) = setup(o)?;
    let threads = rayon::current_num_threads();
    let mut state = State::new(&setup, p);
    let mut solver = Solver::new(&setup, &mut state);
    // Warm-up, as the peer script does before timing (it compiles its kernels there).
    for _ in 0..50 {
        step(&setup, &mut state, &mut solver, dt).map_err(|e| e.to_string())?;
    }
    let c0 = cpu_seconds();
    let t0 = Instant::now();
    // Step from inside the pool, so parallel stages start on a worker thread.
    rayon::scope(|_| {
        for _ in 0..o.steps {
            step(&setup, &mut state, &mut solver, dt)?;
        }
        Ok::<(), grains_mpm::Unstable>(())
    })
    .map_err(|e| e.to_string())?;
    let secs = t0.elapsed().as_secs_f64();
    let cpu = c0.and_then(|c0| Some(cpu_seconds()? - c0));
    let work = o.particles as f64 * o.steps as f64;
    let mut r = Report::default();
    r.line("particles", o.particles);
    r.line("grid", format!("{0}x{0}", o.grid));
    r.line("bodies", o.bodies);
    r.line("shape", format!("{}, update: {}", o.shape, o.update));
    r.line("material", o.material.as_str());
    r.line(
        "steps",
        format!("{} (after 50 warm-up steps), dt = {dt:.3e} s", o.steps),
    );
    r.line("threads", threads);
    r.line("wall time", format!("{secs:.3} s"));
    if let Some(cpu) = cpu {
        r.line("cpu time", format!("{cpu:.3} s"));
        r.line("particle-steps per cpu-s", format!("{:.4e}", work / cpu));
    }
    let d = grains_mpm::diagnostics::measure(&setup, &state.particles, &solver.layout().bodies);
    r.line(
        "dissipated",
        format!(
            "{:.4e} J/m (largest plastic strain {:.4e})",
            d.dissipated,
            d.bodies.iter().map(|b| b.plastic_max).fold(0.0, f64::max)
        ),
    );
    r.line(
        "state-hash",
        format!(
            "{:016x}",
            grains_mpm::diagnostics::state_hash(&state.particles)
        ),
    );
    r.rate = work / secs;
    Ok(r)
}
