//! The ring's grains as a sample reads them: every grain of every rank, in ascending
//! id, so that the ring's figures (radii, band, spall, the kinetic and rotational
//! energies) are added in one order whatever the storage order and the rank count.

use glam::DVec2;
use grains_dem::diagnostics::contact_pressure;
use grains_dem::{Reduce, Setup, State};

/// The ring's grains in ascending id.
#[derive(Clone, Debug, Default)]
pub struct Grains {
    /// Centres (m).
    pub pos: Vec<DVec2>,
    /// Velocities (m/s).
    pub vel: Vec<DVec2>,
    /// Radii (m).
    pub radius: Vec<f64>,
    /// Masses (kg/m).
    pub mass: Vec<f64>,
    /// Mean contact stress ([`contact_pressure`], Pa).
    pub pressure: Vec<f64>,
    /// Rotational kinetic energy of the whole ring (J/m).
    pub rotational: f64,
}

/// Words of one grain: id, centre, velocity, radius, mass, pressure, spin, 1/inertia.
const WORDS: usize = 10;

/// The grains of `s` that `owns` names (this rank's own), with every other rank's
/// through `comm`, in ascending id.
pub fn gathered(
    setup: &Setup,
    s: &State,
    comm: &dyn Reduce,
    owns: &dyn Fn(usize) -> bool,
) -> Grains {
    let p = &s.particles;
    let pressure = contact_pressure(setup, s, &[]);
    let mut words = Vec::with_capacity(p.len() * WORDS);
    for i in (0..p.len()).filter(|&i| owns(i)) {
        words.push(u64::from(p.id[i]));
        words.extend(
            [
                p.pos[i].x,
                p.pos[i].y,
                p.vel[i].x,
                p.vel[i].y,
                p.radius[i],
                p.mass(i),
                pressure[i],
                p.omega[i],
                p.inv_inertia[i],
            ]
            .map(f64::to_bits),
        );
    }
    if comm.ranks() > 1 {
        words = comm.gather(words);
    }
    let mut rows: Vec<&[u64]> = words.chunks_exact(WORDS).collect();
    rows.sort_unstable_by_key(|w| w[0]);
    let f = |w: &[u64], k: usize| f64::from_bits(w[k]);
    Grains {
        pos: rows.iter().map(|w| DVec2::new(f(w, 1), f(w, 2))).collect(),
        vel: rows.iter().map(|w| DVec2::new(f(w, 3), f(w, 4))).collect(),
        radius: rows.iter().map(|w| f(w, 5)).collect(),
        mass: rows.iter().map(|w| f(w, 6)).collect(),
        pressure: rows.iter().map(|w| f(w, 7)).collect(),
        rotational: rows.iter().map(|w| 0.5 * f(w, 8) * f(w, 8) / f(w, 9)).sum(),
    }
}
