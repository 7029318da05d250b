//! `grains check`: validate a scenario and print what a run would do, without running.

use super::{assemble, scenario};
use crate::fail;
use serde::Serialize;
use std::path::Path;
use std::process::ExitCode;

/// Figures derived from a scenario.
#[derive(Serialize)]
struct Derived {
    name: String,
    particles: usize,
    materials: usize,
    walls: usize,
    dt: f64,
    dt_critical: f64,
    steps: u64,
    duration: f64,
    skin: f64,
    memory_bytes_estimate: u64,
}

/// Bytes per particle: state (≈ 100 B), neighbour list with history and per-entry forces
/// (≈ 4 entries × 40 B), reverse index and skin bookkeeping (≈ 30 B), wall springs.
fn memory_estimate(particles: usize, walls: usize) -> u64 {
    (particles as u64) * (100 + 160 + 30 + 8 * walls as u64) + (1 << 20)
}

/// Runs the command on scenario `text` read from `origin`; relative paths are read
/// from `base`.
pub fn cmd_check(text: &str, origin: &str, base: &Path, json: bool) -> ExitCode {
    let scn = match scenario::parse(text, origin) {
        Ok(v) => v,
        Err(e) => return fail(1, &e),
    };
    let asm = match assemble::assemble(&scn, base) {
        Ok(a) => a,
        Err(e) => return fail(1, &format!("{origin}: {e}")),
    };
    let d = Derived {
        name: scn.name.clone(),
        particles: asm.particles.len(),
        materials: asm.setup.materials.len(),
        walls: asm.setup.walls.len(),
        dt: asm.setup.dt,
        dt_critical: asm.dt_critical,
        steps: asm.steps,
        duration: scn.run.duration,
        skin: asm.setup.skin,
        memory_bytes_estimate: memory_estimate(asm.particles.len(), asm.setup.walls.len()),
    };
    if json {
        match serde_json::to_string_pretty(&d) {
            Ok(s) => println!("{s}"),
            Err(e) => return fail(1, &e.to_string()),
        }
    } else {
        println!("scenario     {}", d.name);
        if !scn.description.is_empty() {
            println!("             {}", scn.description.trim());
        }
        println!("particles    {}", d.particles);
        println!("materials    {}", d.materials);
        println!("walls        {}", d.walls);
        println!(
            "time step    {:.4e} s ({:.3} of the stable limit {:.4e} s)",
            d.dt,
            d.dt / d.dt_critical,
            d.dt_critical
        );
        println!("duration     {:.4e} s = {} steps", d.duration, d.steps);
        println!("skin         {:.4e} m", d.skin);
        println!(
            "memory       ≈ {:.1} MB",
            d.memory_bytes_estimate as f64 / 1e6
        );
        println!("ok");
    }
    ExitCode::SUCCESS
}
