//! `grains bench dem`: time the DEM engine on a dense bed with the peer benchmark's
//! physics (LAMMPS `gran/hooke/history`, kn = 4000, kt = 2/7 kn, γn = 87, γt = γn/2,
//! μ = 0.3, density 1, g = 1, Δt = 5·10⁻⁴, skin 0.1, frictional floor, periodic x).

use super::{peak_memory_mb, Report};
use crate::estimate::{rate, Estimate};
use glam::DVec2;
use grains_core::rng;
use grains_dem::{step, ContactModel, Domain, Material, Particles, Setup, State, Wall, WallShape};
use rand::RngExt;
use std::path::PathBuf;

/// The peer benchmark's time step.
pub const DT: f64 = 5e-4;

/// Which bed to time.
#[derive(Clone, Debug)]
pub enum Bed {
    /// `n` disks on a lattice over a floor, built here.
    Built(usize),
    /// A LAMMPS data file, repeated `tile` times along x.
    LammpsData(PathBuf, usize),
}

/// Times `steps` steps of the DEM engine on `bed`, on the current thread pool. A bed
/// too large for memory is refused before it is built.
pub fn run(bed: &Bed, steps: u64) -> Result<Report, String> {
    let (setup, p) = build(bed, steps)?;
    let particles = p.len();
    let mut state = State::new(&setup, p);
    let mut r = super::timed(particles, steps, || step(&setup, &mut state, DT));
    r.line("neighbour builds", state.contacts.builds);
    let d = grains_dem::diagnostics::measure(&setup, &state);
    r.line(
        "list entries per particle",
        format!(
            "{:.3}, contacts per particle: {:.3}",
            state.contacts.len() as f64 / particles as f64,
            d.mean_coordination(particles)
        ),
    );
    r.line(
        "state-hash",
        format!("{:016x}", grains_dem::diagnostics::state_hash(&state)),
    );
    if let Some(mb) = peak_memory_mb() {
        r.line("peak memory", format!("{mb:.0} MB"));
    }
    Ok(r)
}

/// The bed to time, for `steps` timed steps: refused before it is built when the
/// arguments are out of range or it would not fit in memory.
pub fn build(bed: &Bed, steps: u64) -> Result<(Setup, Particles), String> {
    let threads = rayon::current_num_threads();
    if steps == 0 {
        return Err("--steps = 0: must be at least 1 (a rate needs timed steps)".into());
    }
    let (n, what) = match bed {
        Bed::Built(0) => return Err("--particles = 0: must be at least 1".into()),
        Bed::Built(n) => (*n as u64, "--particles".to_string()),
        Bed::LammpsData(_, 0) => return Err("--tile = 0: must be at least 1".into()),
        Bed::LammpsData(path, tile) => (
            grains_core::lammps_data::atom_count(path).unwrap_or(0) * *tile as u64,
            format!("--lammps-data {} --tile {tile}", path.display()),
        ),
    };
    Estimate::new(n, steps, n.saturating_mul(330), rate::DEM, threads).fits_memory(&what)?;
    let (setup, p) = match bed {
        Bed::Built(n) => peer_bed(*n),
        Bed::LammpsData(path, tile) => lammps_bed(path, *tile)?,
    };
    Ok((setup, p))
}

/// The peer benchmark's physics in a box `lo..hi`, periodic in x, floor at y = 0.
pub fn peer_setup(lo: DVec2, hi: DVec2) -> Setup {
    let material = Material {
        name: "bench".into(),
        density: 1.0,
        youngs: None,
        poisson: None,
        restitution: None,
        friction: None,
        // LAMMPS `fix nve/sphere` (no `disc` keyword) integrates rotation with I = 0.4 m r².
        inertia_factor: 0.4,
    };
    let model = ContactModel::hooke_history(4000.0, 87.0, 0.3);
    let domain = Domain {
        lo,
        hi,
        periodic: [true, false],
    };
    let floor = Wall {
        name: "floor".into(),
        shape: WallShape::Segment {
            a: [-1e9, 0.0],
            b: [1e9, 0.0],
        },
        material: None,
        motion: Default::default(),
    };
    Setup::new(
        domain,
        vec![material],
        model,
        vec![floor],
        DVec2::new(0.0, -1.0),
        0.1,
    )
    .expect("the benchmark set-up is valid")
}

/// A bed of `n` disks (d uniform in [0.88, 0.98)) on a square lattice of pitch 1 over a
/// floor, about 2.3 times wider than high, with the peer benchmark's contact law.
pub fn peer_bed(n: usize) -> (Setup, Particles) {
    let nx = ((2.27 * n as f64).sqrt().ceil() as usize).max(4);
    let ny = n.div_ceil(nx);
    let setup = peer_setup(DVec2::ZERO, DVec2::new(nx as f64, ny as f64 + 2.0));
    let mut rng = rng::seeded(4711);
    let mut p = Particles::default();
    for k in 0..n {
        let at = DVec2::new((k % nx) as f64 + 0.5, (k / nx) as f64 + 0.5);
        let d = 0.88 + 0.1 * rng.random::<f64>();
        p.push(at, 0.5 * d, 1.0, 0.4, 0, DVec2::ZERO, 0.0);
    }
    (setup, p)
}

/// The bed of a LAMMPS data file with the peer benchmark's physics: disc masses of
/// density 1 (as `set density/disc 1.0` in `in.bench.lmp`), positions, velocities and
/// angular velocities from the file, the box's x bounds as the periodic length.
pub fn lammps_bed(path: &std::path::Path, tile: usize) -> Result<(Setup, Particles), String> {
    let data = grains_core::lammps_data::read(path).map_err(|e| e.to_string())?;
    if data.atoms.is_empty() {
        return Err(format!("{}: no atoms", path.display()));
    }
    data.require_dimension(2, &path.display().to_string())?;
    let top = data
        .atoms
        .iter()
        .map(|a| a.pos[1])
        .fold(data.hi[1], f64::max);
    let width = data.hi[0] - data.lo[0];
    let setup = peer_setup(
        DVec2::new(data.lo[0], data.lo[1].min(0.0)),
        DVec2::new(data.lo[0] + width * tile as f64, top + 1.0),
    );
    let mut p = Particles::default();
    for k in 0..tile {
        for a in &data.atoms {
            if !(a.diameter.is_finite() && a.diameter > 0.0) {
                return Err(format!(
                    "{}: atom {} has diameter {}: must be > 0",
                    path.display(),
                    a.id,
                    a.diameter
                ));
            }
            // Fold into the file's own periodic box, then shift to copy k.
            let x = data.lo[0] + (a.pos[0] - data.lo[0]).rem_euclid(width) + width * k as f64;
            p.push(
                DVec2::new(x, a.pos[1]),
                0.5 * a.diameter,
                1.0,
                0.4,
                0,
                DVec2::new(a.vel[0], a.vel[1]),
                a.omega[2],
            );
        }
    }
    Ok((setup, p))
}
