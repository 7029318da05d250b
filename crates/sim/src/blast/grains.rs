//! The ring's grains as a sample (and the dispersal analysis) reads them: every grain
//! of every rank, in ascending id, so that the ring's figures (radii, band, spall, the
//! kinetic and rotational energies, the dispersal's fields) are added in one order
//! whatever the storage order and the rank count.

use crate::dispersal::Frame;
use glam::{DMat2, DVec2};
use grains_dem::diagnostics::contact_pressure;
use grains_dem::stress::particle_stress;
use grains_dem::{Particles, Reduce, Setup, State};

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
    let words = rows(p, owns, |i| [pressure[i], p.omega[i], p.inv_inertia[i]]);
    let words = every_rank(words, comm);
    let rows = by_id(&words, WORDS);
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

/// Words of one grain in a dispersal frame: id, centre, velocity, radius, mass, stress.
const FRAME_WORDS: usize = 11;

/// The dispersal analysis's frame of the grains of `s` that `owns` names, with every
/// other rank's through `comm`, in ascending id: the same frame on any rank count, each
/// grain's stress added in its partners' id order ([`particle_stress`]). The time and
/// the charge's extent are the caller's.
pub fn frame(setup: &Setup, s: &State, comm: &dyn Reduce, owns: &dyn Fn(usize) -> bool) -> Frame {
    let p = &s.particles;
    let stress = particle_stress(setup, s);
    let words = rows(p, owns, |i| {
        let m = stress[i];
        [m.x_axis.x, m.x_axis.y, m.y_axis.x, m.y_axis.y]
    });
    let words = every_rank(words, comm);
    let rows = by_id(&words, FRAME_WORDS);
    let f = |w: &[u64], k: usize| f64::from_bits(w[k]);
    let v = |w: &[u64], k: usize| DVec2::new(f(w, k), f(w, k + 1));
    Frame {
        time: 0.0,
        id: rows.iter().map(|w| w[0] as u32).collect(),
        pos: rows.iter().map(|w| v(w, 1)).collect(),
        vel: rows.iter().map(|w| v(w, 3)).collect(),
        radius: rows.iter().map(|w| f(w, 5)).collect(),
        mass: rows.iter().map(|w| f(w, 6)).collect(),
        stress: Some(
            rows.iter()
                .map(|w| DMat2::from_cols(v(w, 7), v(w, 9)))
                .collect(),
        ),
        charge_radius: None,
    }
}

/// For each grain that `owns` names: its id, centre, velocity, radius and mass, then
/// the `K` words of `more`.
fn rows<const K: usize>(
    p: &Particles,
    owns: &dyn Fn(usize) -> bool,
    more: impl Fn(usize) -> [f64; K],
) -> Vec<u64> {
    let mut words = Vec::with_capacity(p.len() * (7 + K));
    for i in (0..p.len()).filter(|&i| owns(i)) {
        words.push(u64::from(p.id[i]));
        let (x, v) = (p.pos[i], p.vel[i]);
        let motion = [x.x, x.y, v.x, v.y, p.radius[i], p.mass(i)];
        words.extend(motion.into_iter().chain(more(i)).map(f64::to_bits));
    }
    words
}

/// This rank's `words` followed by every other rank's, in rank order.
fn every_rank(words: Vec<u64>, comm: &dyn Reduce) -> Vec<u64> {
    if comm.ranks() > 1 {
        comm.gather(words)
    } else {
        words
    }
}

/// The rows of `width` words, each led by an id, in ascending id.
fn by_id(words: &[u64], width: usize) -> Vec<&[u64]> {
    let mut rows: Vec<&[u64]> = words.chunks_exact(width).collect();
    rows.sort_unstable_by_key(|w| w[0]);
    rows
}
