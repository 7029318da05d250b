//! `grains check` for DEM: the particle count and memory come from the scenario's
//! sources without building them, so a run too large for memory is refused before any
//! allocation; then the scenario is assembled in full and its step derived.

use super::assemble::assemble;
use super::scenario::{ParticleSource, Scenario};
use crate::check::{Derived, Line};
use crate::estimate::{self, rate, Estimate};
use crate::source::Source;

/// Bytes per particle: state (≈ 100 B), neighbour list with its owners, history and
/// per-entry forces (≈ 4 entries × 44 B), reverse index and skin bookkeeping (≈ 30 B),
/// and one wall spring per wall; the 1.8 M-disk bed peaked at 585 MB (≈ 325 B per disk)
/// before the entries' owners were kept (≈ 11 B per disk more).
fn bytes_per_particle(walls: usize) -> u64 {
    346 + 8 * walls as u64
}

/// The number of particles the scenario's sources hold, counted without building them
/// (a file's lines, a data file's header).
pub fn count(s: &Scenario, src: &Source) -> u64 {
    s.particles
        .iter()
        .map(|p| match p {
            ParticleSource::List { disks, .. } => disks.len() as u64,
            ParticleSource::Lattice { count, .. } => *count as u64,
            ParticleSource::File { path, .. } => {
                estimate::packing_lines(&src.base.join(path)).unwrap_or(0)
            }
            ParticleSource::LammpsData { path, .. } => {
                grains_core::lammps_data::atom_count(&src.base.join(path)).unwrap_or(0)
            }
        })
        .sum()
}

/// The memory a run needs, checked against what is available, before anything is built.
pub fn fits(s: &Scenario, src: &Source, threads: usize) -> Result<u64, String> {
    let n = count(s, src);
    let e = Estimate::new(
        n,
        0,
        n * bytes_per_particle(s.walls.len()) + (1 << 20),
        rate::DEM,
        threads,
    );
    e.fits_memory(&format!("{}: particles", src.origin))?;
    Ok(n)
}

/// What a run of `n` particles among `walls` walls over `steps` steps costs.
pub fn cost(n: u64, walls: usize, steps: u64, threads: usize) -> Estimate {
    Estimate::new(
        n,
        steps,
        n * bytes_per_particle(walls) + (1 << 20),
        rate::DEM,
        threads,
    )
}

/// What `grains check` prints for a DEM scenario.
pub fn derived(s: &Scenario, src: &Source, threads: usize) -> Result<Derived, String> {
    fits(s, src, threads)?;
    let a = assemble(s, &src.base).map_err(|e| format!("{}: {e}", src.origin))?;
    let n = a.particles.len() as u64;
    let walls = a.setup.walls.len();
    let mut d = lines(
        (&s.name, &s.description),
        Vec::new(),
        &[n, a.setup.materials.len() as u64, walls as u64],
        (a.dt, a.dt_critical, s.run.duration, a.steps),
        a.setup.skin,
    );
    d.cost(&cost(n, walls, a.steps, threads));
    d.warnings.extend(super::plausible::warnings(s, &a));
    Ok(d)
}

/// What `grains check` prints for a DEM scenario of either dimension: its (name,
/// description), the `extra` lines, the particle, material and wall counts, the step
/// (dt, critical dt, duration, steps) and the skin.
pub fn lines(
    (name, description): (&str, &str),
    extra: Vec<Line>,
    &[n, materials, walls]: &[u64; 3],
    (dt, dt_critical, duration, steps): (f64, f64, f64, u64),
    skin: f64,
) -> Derived {
    let mut d = Derived {
        lines: Derived::head(name, "dem", description),
        ..Default::default()
    };
    d.lines.extend(extra);
    d.lines.extend([
        Line::new("particles", n, n.to_string()),
        Line::new("materials", materials, materials.to_string()),
        Line::new("walls", walls, walls.to_string()),
    ]);
    d.lines
        .extend(Derived::fixed_step(dt, dt_critical, duration, steps));
    d.lines
        .push(Line::new("skin", skin, format!("{skin:.4e} m")));
    d
}
