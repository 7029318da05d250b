//! `grains check` for MPM: validate a scenario and print what a run would do.

use super::assemble::Assembled;
use super::scenario::Scenario;
use crate::fail;
use serde::Serialize;
use std::process::ExitCode;

/// Figures derived from a scenario.
#[derive(Serialize)]
struct Derived {
    name: String,
    engine: &'static str,
    particles: usize,
    bodies: Vec<BodyLine>,
    cells: [usize; 2],
    cell_size: f64,
    shape: String,
    update: String,
    wave_speed_max: f64,
    dt: f64,
    dt_critical: f64,
    steps: u64,
    duration: f64,
    memory_bytes_estimate: u64,
}

#[derive(Serialize)]
struct BodyLine {
    name: String,
    points: usize,
    area: f64,
    mass: f64,
    rigid: bool,
}

/// Prints the derived figures (text or JSON).
pub fn print(scn: &Scenario, asm: &Assembled, json: bool) -> ExitCode {
    let setup = &asm.setup;
    let bodies: Vec<BodyLine> = setup
        .bodies
        .iter()
        .enumerate()
        .map(|(k, b)| BodyLine {
            name: b.name.clone(),
            points: asm.counts[k],
            area: asm.areas[k],
            mass: asm.areas[k] * setup.materials[b.material].density(),
            rigid: b.motion != grains_mpm::Motion::Free,
        })
        .collect();
    let nodes = setup.grid.stored()[0] * setup.grid.stored()[1];
    let d = Derived {
        name: scn.name.clone(),
        engine: "mpm",
        particles: asm.particles.len(),
        bodies,
        cells: setup.grid.cells,
        cell_size: setup.grid.h,
        shape: scn.method.shape.clone(),
        update: scn.method.update.clone(),
        wave_speed_max: setup
            .materials
            .iter()
            .map(|m| m.wave_speed())
            .fold(0.0, f64::max),
        dt: setup.dt,
        dt_critical: asm.dt_critical,
        steps: asm.steps,
        duration: scn.run.duration,
        // Points: ~170 B of state; grid: one 64 B record + 32 B kinematics per node and
        // body patch, plus the 80 B global sums with several bodies.
        memory_bytes_estimate: asm.particles.len() as u64 * 170 + nodes as u64 * (96 + 80),
    };
    if json {
        return match serde_json::to_string_pretty(&d) {
            Ok(s) => {
                println!("{s}");
                ExitCode::SUCCESS
            }
            Err(e) => fail(1, &e.to_string()),
        };
    }
    println!("scenario     {} (mpm)", d.name);
    if !scn.description.is_empty() {
        println!("             {}", scn.description.trim());
    }
    println!(
        "grid         {} × {} cells of {:.4e} m, {} shape functions, {} update",
        d.cells[0], d.cells[1], d.cell_size, d.shape, d.update
    );
    println!("points       {}", d.particles);
    for b in &d.bodies {
        println!(
            "  body {:12} {:7} points, area {:.5e} m², mass {:.5e} kg/m{}",
            b.name,
            b.points,
            b.area,
            b.mass,
            if b.rigid { ", rigid" } else { "" }
        );
    }
    println!(
        "wave speed   {:.4e} m/s (plane-strain dilatational, fastest material)",
        d.wave_speed_max
    );
    println!(
        "time step    {:.4e} s ({:.3} of the stable limit {:.4e} s)",
        d.dt,
        d.dt / d.dt_critical,
        d.dt_critical
    );
    println!("duration     {:.4e} s = {} steps", d.duration, d.steps);
    println!(
        "memory       ≈ {:.1} MB",
        d.memory_bytes_estimate as f64 / 1e6
    );
    println!("ok");
    ExitCode::SUCCESS
}
