//! `grains check` for MPM: the point count and grid size come from the scenario's shapes
//! and grid without filling them, so a run too large for memory is refused before any
//! allocation; then the scenario is assembled in full and its step derived.

use super::run::prepare;
use super::scenario::Scenario;
use crate::check::{Derived, Line};
use crate::estimate::{rate, Estimate};
use crate::source::Source;

/// Points: ~200 B of state (kinematics, stress, plastic strain, bond, energy accounts)
/// plus 24 B per Maxwell branch; grid: one 64 B record + 32 B kinematics per node and
/// body patch, plus the 80 B global sums with several bodies.
fn memory(points: u64, nodes: u64, branches: u64) -> u64 {
    // Saturating: a zero cell size asks for "infinitely" many nodes, which the memory
    // check then refuses instead of overflowing.
    points
        .saturating_mul(200 + 24 * branches)
        .saturating_add(nodes.saturating_mul(96 + 80))
        .saturating_add(1 << 20)
}

/// Maxwell branches each point stores: the most any material has.
fn branches(s: &Scenario) -> u64 {
    s.materials.iter().map(|m| m.branches()).max().unwrap_or(0) as u64
}

/// Points and grid nodes the scenario asks for, from its shapes' areas.
fn size(s: &Scenario) -> (u64, u64) {
    let g = &s.grid;
    // A cell size the assembly will refuse (naming its key) counts as nothing here.
    if !(g.cell_size.is_finite() && g.cell_size > 0.0) {
        return (0, 0);
    }
    let pitch = g.cell_size / g.particles_per_cell.max(1) as f64;
    let points: f64 = s
        .bodies
        .iter()
        .map(|b| b.geometry.area() / (pitch * pitch))
        .filter(|n| n.is_finite())
        .sum();
    let cells = |k: usize| ((g.hi[k] - g.lo[k]) / g.cell_size).abs();
    let nodes = (cells(0) + 1.0) * (cells(1) + 1.0);
    let clamp = |v: f64| {
        if v.is_finite() {
            v.min(1e19) as u64
        } else {
            u64::MAX
        }
    };
    (clamp(points), clamp(nodes))
}

/// The memory a run needs, checked against what is available, before anything is built.
pub fn fits(s: &Scenario, src: &Source, threads: usize) -> Result<(), String> {
    let (points, nodes) = size(s);
    Estimate::new(
        points,
        0,
        memory(points, nodes, branches(s)),
        rate::MPM,
        threads,
    )
    .fits_memory(&format!("{}: bodies and grid", src.origin))
}

/// What a run of `n` points with `branches` Maxwell branches each on `nodes` grid nodes
/// over `steps` steps costs.
pub fn cost(n: u64, nodes: u64, branches: u64, steps: u64, threads: usize) -> Estimate {
    Estimate::new(n, steps, memory(n, nodes, branches), rate::MPM, threads)
}

/// What `grains check` prints for an MPM scenario.
pub fn derived(s: &Scenario, src: &Source, threads: usize) -> Result<Derived, String> {
    let s = &super::packing::expanded(s, src)?;
    fits(s, src, threads)?;
    let a = prepare(s, src)?;
    let setup = &a.setup;
    let mut d = Derived {
        lines: Derived::head(&s.name, "mpm", &s.description),
        ..Default::default()
    };
    d.lines.push(Line::new(
        "grid",
        serde_json::json!({"cells": setup.grid.cells, "cell_size": setup.grid.h}),
        format!(
            "{} × {} cells of {:.4e} m, {} shape functions, {} update",
            setup.grid.cells[0], setup.grid.cells[1], setup.grid.h, s.method.shape, s.method.update
        ),
    ));
    let n = a.particles.len() as u64;
    d.lines
        .push(Line::new("particles", n, format!("{n} material points")));
    let bodies: Vec<serde_json::Value> = setup
        .bodies
        .iter()
        .enumerate()
        .map(|(k, b)| {
            serde_json::json!({
                "name": b.name,
                "material": setup.materials[b.material].name(),
                "points": a.counts[k],
                "area": a.areas[k],
                "mass": a.areas[k] * setup.materials[b.material].density(),
                "rigid": b.motion != grains_mpm::Motion::Free,
                "temperature_change": b.temperature.as_ref().map(|h| h.at(s.run.duration) - h.at(0.0)),
            })
        })
        .collect();
    let text: Vec<String> = bodies
        .iter()
        .map(|b| {
            format!(
                "{} ({}, {} points, area {:.5e} m², mass {:.5e} kg/m{}{})",
                b["name"].as_str().unwrap_or_default(),
                b["material"].as_str().unwrap_or_default(),
                b["points"],
                b["area"].as_f64().unwrap_or(f64::NAN),
                b["mass"].as_f64().unwrap_or(f64::NAN),
                if b["rigid"] == true { ", rigid" } else { "" },
                b["temperature_change"]
                    .as_f64()
                    .map(|d| format!(", ΔT = {d} over the run"))
                    .unwrap_or_default()
            )
        })
        .collect();
    d.lines.push(Line::new("bodies", bodies, text.join("; ")));
    let count = setup.bodies.len();
    let bonds: Vec<serde_json::Value> = (0..count)
        .flat_map(|i| (i + 1..count).map(move |j| (i, j)))
        .filter_map(|(i, j)| match setup.contact.get(i, j) {
            grains_mpm::ContactLaw::Bonded { strength, mu } => Some(serde_json::json!({
                "bodies": [setup.bodies[i].name, setup.bodies[j].name],
                "strength": strength,
                "mu": mu,
            })),
            _ => None,
        })
        .collect();
    if !bonds.is_empty() {
        // A packing bonds hundreds of grains: the first pairs, then how many more.
        const SHOWN: usize = 6;
        let text: Vec<String> = bonds
            .iter()
            .take(SHOWN)
            .map(|b| {
                format!(
                    "{}–{}: {:e} Pa, then μ = {}",
                    b["bodies"][0].as_str().unwrap_or_default(),
                    b["bodies"][1].as_str().unwrap_or_default(),
                    b["strength"].as_f64().unwrap_or(f64::NAN),
                    b["mu"]
                )
            })
            .collect();
        let more = match bonds.len().saturating_sub(SHOWN) {
            0 => String::new(),
            n => format!("; and {n} more pairs"),
        };
        d.lines
            .push(Line::new("bonds", bonds, text.join("; ") + &more));
    }
    let c = setup
        .materials
        .iter()
        .map(|m| m.wave_speed())
        .fold(0.0, f64::max);
    d.lines.push(Line::new(
        "wave_speed_max",
        c,
        format!("{c:.4e} m/s (plane-strain dilatational, fastest material)"),
    ));
    d.lines.extend(Derived::fixed_step(
        a.dt,
        a.dt_critical,
        s.run.duration,
        a.steps,
    ));
    let nodes = (setup.grid.stored()[0] * setup.grid.stored()[1]) as u64;
    d.cost(&cost(n, nodes, branches(s), a.steps, threads));
    Ok(d)
}
