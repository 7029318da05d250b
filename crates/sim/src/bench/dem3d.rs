//! `grains bench dem --dim 3`: time the 3D DEM engine on a settled bed of spheres read
//! from a LAMMPS data file, with the physics of the peer deck `in.bench3d.lmp`
//! (`pair_style granular` `hertz/material 1e5 0.5 0.3 damping tsuji tangential mindlin
//! NULL 1.0 0.4`, the same law on a floor at z = 0, `nve/sphere`, Δt = 5·10⁻⁴, skin 0.2,
//! g = 1 along −z, periodic in x and y).
//!
//! Besides the rate it prints what `bench/in.check3d.lmp` prints after the same steps
//! (translational and rotational kinetic energy, the highest sphere top, the floor's
//! load), so that the speed comparison can be seen to be of the same physics.

use super::{peak_memory_mb, Report};
use crate::estimate::{rate, Estimate};
use glam::DVec3;
use grains_dem3d::granular::{Damping, GranularParams, Normal, Tangential};
use grains_dem3d::{
    step, ContactModel, Domain, Material, PairTable, Particles, Setup, State, Wall, WallShape,
};
use std::path::Path;

/// The deck's time step.
pub const DT: f64 = 5e-4;

/// The deck's neighbour skin.
pub const SKIN: f64 = 0.2;

/// The floor's material: its law is `fix wall/gran`'s ([`floor_law`]).
const FLOOR: u16 = 1;

/// Bytes per sphere the estimate assumes before the bed is built.
const BYTES_PER_SPHERE: u64 = 1000;

/// Times `steps` steps of the 3D engine on the bed of the data file `path`, on the
/// current thread pool.
pub fn run(path: &Path, steps: u64) -> Result<Report, String> {
    let threads = rayon::current_num_threads();
    if steps == 0 {
        return Err("--steps = 0: must be at least 1 (a rate needs timed steps)".into());
    }
    let n = grains_core::lammps_data::atom_count(path).unwrap_or(0);
    Estimate::new(
        n,
        steps,
        n.saturating_mul(BYTES_PER_SPHERE),
        rate::DEM,
        threads,
    )
    .fits_memory(&format!("--lammps-data {}", path.display()))?;
    let (setup, p) = lammps_bed(path)?;
    let particles = p.len();
    let mut state = State::new(&setup, p);
    let mut r = super::timed(particles, steps, || step(&setup, &mut state, DT));
    r.lines.insert(0, ("dimension".into(), "3".into()));
    r.line("neighbour builds", state.contacts.builds);
    let d = grains_dem3d::diagnostics::measure(&setup, &state);
    r.line(
        "list entries per particle",
        format!(
            "{:.3}, contacts per particle: {:.3}",
            state.contacts.len() as f64 / particles as f64,
            d.mean_coordination(particles)
        ),
    );
    // The figures bench/in.check3d.lmp prints (thermo `ke c_rke c_top f_floorz`).
    r.line(
        "kinetic energy",
        format!("{:.10e}", d.kinetic_translational),
    );
    r.line(
        "rotational energy",
        format!("{:.10e}", d.kinetic_rotational),
    );
    let p = &state.particles;
    let top = (0..particles)
        .map(|i| p.pos[i].z + p.radius[i])
        .fold(f64::MIN, f64::max);
    r.line("top", format!("{top:.10e}"));
    let floor = state.wall_loads.first().map_or(0.0, |l| -l.force.z);
    r.line("floor force", format!("{floor:.10e}"));
    r.line(
        "state-hash",
        format!("{:016x}", grains_dem3d::diagnostics::state_hash(&state)),
    );
    if let Some(mb) = peak_memory_mb() {
        r.line("peak memory", format!("{mb:.0} MB"));
        let bytes = mb * 1024.0 * 1024.0 / particles as f64;
        r.line("peak memory per sphere", format!("{bytes:.0} B"));
    }
    Ok(r)
}

/// The deck's contact law: `hertz/material 1e5 0.5 0.3 damping tsuji tangential mindlin
/// NULL 1.0 0.4`.
pub fn deck_law() -> GranularParams {
    GranularParams::lammps(
        Normal::HertzMaterial,
        1.0e5,
        Damping::Tsuji,
        0.5,
        0.3,
        Tangential::Mindlin,
        None,
        1.0,
        0.4,
    )
}

/// The deck's law on the floor, as `fix wall/gran granular` (29 Sep 2021) resolves the
/// same keywords: k = E/(2(1 − ν)) · 1.333333333333333 (not (4/3)E*) and Mindlin's
/// k_t = E/4 (2 − ν)(1 + ν) (not 8G*), as `crates/dem/tests/lammps/SPEC.md` §8 reads
/// them in its source.
pub fn floor_law() -> GranularParams {
    let (e, nu) = (1.0e5, 0.3);
    GranularParams {
        kn: e / (2.0 * (1.0 - nu)) * 1.333333333333333,
        kt: e / 4.0 * (2.0 - nu) * (1.0 + nu),
        ..deck_law()
    }
}

/// The deck's set-up over the box `lo..hi`: periodic in x and y, the floor z = 0.
pub fn deck_setup(lo: DVec3, hi: DVec3) -> Setup {
    let material = |name: &str| Material {
        name: name.into(),
        density: 1.0,
        youngs: None,
        poisson: None,
        restitution: None,
        friction: None,
        inertia_factor: 0.4,
    };
    // The linear model is a placeholder: the granular table below replaces it for every
    // pair and wall.
    let model = ContactModel::unused();
    let domain = Domain {
        lo,
        hi,
        periodic: [true, true, false],
    };
    let floor = Wall {
        name: "floor".into(),
        shape: WallShape::Plane {
            point: [0.0; 3],
            normal: [0.0, 0.0, 1.0],
        },
        material: Some(FLOOR),
        motion: Default::default(),
    };
    let mut setup = Setup::new(
        domain,
        vec![material("bench3d"), material("floor")],
        model,
        vec![floor],
        DVec3::new(0.0, 0.0, -1.0),
        SKIN,
    )
    .expect("the benchmark set-up is valid");
    setup.granular = Some(PairTable::from_fn(2, |a, b| {
        if a == FLOOR as usize || b == FLOOR as usize {
            floor_law()
        } else {
            deck_law()
        }
    }));
    setup
}

/// The bed of a 3D LAMMPS data file with the deck's physics: each sphere's mass from its
/// diameter and density as LAMMPS's (m = 4/3 π r³ ρ, I = 2/5 m r²), positions folded into
/// the file's x and y period, velocities and angular velocities from the file. A 2D file
/// is refused.
pub fn lammps_bed(path: &Path) -> Result<(Setup, Particles), String> {
    let name = path.display().to_string();
    let data = grains_core::lammps_data::read(path).map_err(|e| e.to_string())?;
    if data.atoms.is_empty() {
        return Err(format!("{name}: no atoms"));
    }
    data.require_dimension(3, &name)?;
    let top = data
        .atoms
        .iter()
        .map(|a| a.pos[2] + 0.5 * a.diameter)
        .fold(data.hi[2], f64::max);
    let lo = DVec3::new(data.lo[0], data.lo[1], data.lo[2].min(0.0));
    let hi = DVec3::new(data.hi[0], data.hi[1], top + 1.0);
    let setup = deck_setup(lo, hi);
    let mut p = Particles::default();
    for a in &data.atoms {
        for (what, v) in [("diameter", a.diameter), ("density", a.density)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{name}: atom {} has {what} {v}: must be > 0", a.id));
            }
        }
        let at = setup.domain.wrap(DVec3::from(a.pos));
        p.push(
            at,
            0.5 * a.diameter,
            a.density,
            0.4,
            0,
            DVec3::from(a.vel),
            DVec3::from(a.omega),
        );
    }
    Ok((setup, p))
}
