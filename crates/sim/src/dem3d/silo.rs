//! A silo's discharge through the hole of its floor (a `disk` wall): the mass flux
//! through the slab just under the floor, one orifice radius h thick,
//! W = Σ m_i max(v_i · (−u), 0) / h over the grains in it (u the floor's normal into the
//! silo), sampled at history times and averaged from `after` on. The slab's flux equals
//! the slope of the discharged mass against time when the flow is steady, and needs no
//! catch basin: a silo periodic along its axis recycles what it discharges. Beverloo's
//! law,
//! W = C ρ_b √g (D − k d)^{5/2} (D the orifice's diameter, d the grains' mean diameter,
//! ρ_b the bulk density), is what W is set against.

use super::Dem3;
use glam::DVec3;
use grains_dem3d::{Particles, WallShape};
use serde::{Deserialize, Serialize};

/// The flux through the slab under the orifice against time, from `after` on.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct DischargeWatch {
    wall: usize,
    after: f64,
    samples: Vec<(f64, f64)>,
}

impl DischargeWatch {
    /// Watches the floor `wall` (a disk) from time `after` on.
    pub fn new(wall: usize, after: f64) -> Self {
        DischargeWatch {
            wall,
            after,
            samples: Vec::new(),
        }
    }

    /// Whether it samples at `time`.
    pub fn wants(&self, time: f64) -> bool {
        time >= self.after
    }

    /// Takes one sample of every sphere, `p` (in ascending id: the sum's order).
    pub fn sample(&mut self, sim: &Dem3, p: &Particles) {
        if !self.wants(sim.state.time) {
            return;
        }
        let Some((c, u, diameter)) = orifice(sim, self.wall) else {
            return;
        };
        let h = 0.5 * diameter;
        let flux: f64 = (0..p.len())
            .filter(|&i| (-h..0.0).contains(&(p.pos[i] - c).dot(u)))
            .map(|i| p.mass(i) * (-p.vel[i].dot(u)).max(0.0))
            .sum();
        self.samples.push((sim.state.time, flux / h));
    }

    /// The steady mass flow rate (kg/s), NaN before any sample.
    pub fn rate(&self) -> f64 {
        self.samples.iter().map(|s| s.1).sum::<f64>() / self.samples.len() as f64
    }
}

/// The centre, the unit normal pointing into the silo (against gravity) and the
/// orifice's diameter of the disk wall `w`.
pub fn orifice(sim: &Dem3, w: usize) -> Option<(DVec3, DVec3, f64)> {
    match sim.setup.walls.get(w)?.shape {
        WallShape::Disk {
            centre,
            normal,
            hole,
            ..
        } => {
            let u = DVec3::from(normal).normalize();
            let up = if u.dot(sim.setup.gravity) > 0.0 {
                -u
            } else {
                u
            };
            Some((centre.into(), up, 2.0 * hole))
        }
        _ => None,
    }
}

/// Beverloo's W = C ρ_b √g (D − k d)^{5/2} (kg/s); zero when D ≤ k d.
pub fn beverloo(c: f64, k: f64, rho_b: f64, g: f64, orifice: f64, d: f64) -> f64 {
    c * rho_b * g.sqrt() * (orifice - k * d).max(0.0).powf(2.5)
}
