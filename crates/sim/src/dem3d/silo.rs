//! A silo's discharge through the hole of its floor (a `disk` wall): the mass flux
//! through the slab just under the floor, one orifice radius h thick,
//! W = Σ m_i max(v_i · (−u), 0) / h over the grains in it (u the floor's normal into the
//! silo), sampled at history times and averaged from `after` on. The slab's flux equals
//! the slope of the discharged mass against time when the flow is steady, and needs no
//! catch basin: a silo periodic along its axis recycles what it discharges. Beverloo's
//! law,
//! W = C ρ_b √g (D − k d)^{5/2} (D the orifice's diameter, d the grains' mean diameter,
//! ρ_b the bulk density), is what W is set against.
//!
//! The bed's packing fraction is measured beside it at the same samples, so that ρ_b
//! need not be assumed: the spheres' volume over the measuring volume, counted by
//! centre, in slabs one mean diameter thick inside the silo's cylinder (2 d off its
//! wall), from two orifice diameters above the floor, clear of the converging flow, to
//! three slabs under the bed's surface (the first slab, going up, at under half the
//! densest one's fraction: grains recycled through the top rain onto the bed).

use super::Dem3;
use glam::DVec3;
use grains_dem3d::math::measure;
use grains_dem3d::{Particles, Wall, WallShape};
use serde::{Deserialize, Serialize};

/// The flux through the slab under the orifice against time, from `after` on.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct DischargeWatch {
    wall: usize,
    after: f64,
    samples: Vec<(f64, f64)>,
    /// The bed's packing fraction at each sample where it could be measured (absent
    /// from checkpoints written before it was kept).
    #[serde(default)]
    packings: Vec<f64>,
}

impl DischargeWatch {
    /// Watches the floor `wall` (a disk) from time `after` on.
    pub fn new(wall: usize, after: f64) -> Self {
        DischargeWatch {
            wall,
            after,
            samples: Vec::new(),
            packings: Vec::new(),
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
        if let Some(phi) = bed_packing(&sim.setup.walls, p, (c, u, diameter)) {
            self.packings.push(phi);
        }
    }

    /// The steady mass flow rate (kg/s), NaN before any sample.
    pub fn rate(&self) -> f64 {
        self.samples.iter().map(|s| s.1).sum::<f64>() / self.samples.len() as f64
    }

    /// The bed's mean packing fraction over the samples, NaN where it was never
    /// measured (no silo cylinder about the orifice, or a bed too shallow).
    pub fn packing(&self) -> f64 {
        self.packings.iter().sum::<f64>() / self.packings.len() as f64
    }
}

/// The packing fraction of the bed above the orifice `(c, u, diameter)` (module doc),
/// or `None` without an inner cylinder wall along `u` or without a slab to measure.
fn bed_packing(
    walls: &[Wall],
    p: &Particles,
    (c, u, diameter): (DVec3, DVec3, f64),
) -> Option<f64> {
    let (axis_point, radius) = walls.iter().find_map(|w| match w.shape {
        WallShape::Cylinder {
            point,
            axis,
            radius,
            inside: true,
        } if DVec3::from(axis).normalize().dot(u).abs() > 1.0 - 1e-9 => {
            Some((DVec3::from(point), radius))
        }
        _ => None,
    })?;
    let n = p.len();
    if n == 0 {
        return None;
    }
    let d = 2.0 * p.radius.iter().sum::<f64>() / n as f64;
    let reach = radius - 2.0 * d;
    if reach <= 0.0 {
        return None;
    }
    // A bed is at most n slabs deep: a sphere above that (or not finite, in a run
    // that diverged) is not in it.
    let mut slabs: Vec<f64> = vec![0.0; n];
    for i in 0..n {
        let x = p.pos[i] - axis_point;
        let off_axis = x - x.dot(u) * u;
        let k = (p.pos[i] - c).dot(u) / d;
        let inside = off_axis.length() <= reach && (0.0..n as f64).contains(&k);
        if inside {
            slabs[k as usize] += measure(p.radius[i]);
        }
    }
    let top = slabs.iter().rposition(|&v| v > 0.0).map_or(0, |k| k + 1);
    slabs.truncate(top);
    let slab_volume = std::f64::consts::PI * reach * reach * d;
    let densest = slabs.iter().copied().fold(0.0, f64::max);
    let first = (2.0 * diameter / d).ceil() as usize;
    let surface = (first..slabs.len())
        .find(|&k| slabs[k] < 0.5 * densest)
        .unwrap_or(slabs.len());
    let last = surface.checked_sub(3)?;
    (first <= last).then(|| {
        slabs[first..=last].iter().sum::<f64>() / (slab_volume * (last + 1 - first) as f64)
    })
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Spheres of diameter `d` on a simple cubic lattice of spacing `d`, filling a
    /// cylinder of radius 12.25 d (no site on the measuring radius, 10.25 d) to 30
    /// layers above an orifice at the origin.
    fn lattice(d: f64) -> (Vec<Wall>, Particles) {
        let cylinder = WallShape::Cylinder {
            point: [0.0; 3],
            axis: [0.0, 0.0, 1.0],
            radius: 12.25 * d,
            inside: true,
        };
        let mut p = Particles::default();
        for k in 0..30 {
            for i in -12..=12 {
                for j in -12..=12 {
                    let x = DVec3::new(i as f64, j as f64, k as f64 + 0.5) * d;
                    if x.truncate().length() <= 11.5 * d {
                        p.push(x, 0.5 * d, 2500.0, 0.4, 0, DVec3::ZERO, DVec3::ZERO);
                    }
                }
            }
        }
        (vec![Wall::fixed("silo", cylinder, None)], p)
    }

    #[test]
    fn a_lattice_bed_has_its_packing_fraction() {
        let d = 0.004;
        let (walls, p) = lattice(d);
        let orifice = (DVec3::ZERO, DVec3::Z, 2.0 * d);
        // Per layer, the lattice sites within the measuring radius 12.25 d − 2 d.
        let sites = (-12..=12_i32)
            .flat_map(|i| (-12..=12_i32).map(move |j| (i, j)))
            .filter(|&(i, j)| f64::from(i * i + j * j).sqrt() <= 10.25)
            .count() as f64;
        let area = std::f64::consts::PI * 10.25 * 10.25 * d * d;
        let expected = sites * measure(0.5 * d) / (area * d);
        let phi = bed_packing(&walls, &p, orifice).expect("a bed to measure");
        assert!(
            (phi - expected).abs() < 1e-12 * expected,
            "{phi} against {expected}"
        );
        // π/6 for the lattice, to within the circle's count of sites.
        assert!((phi / (std::f64::consts::PI / 6.0) - 1.0).abs() < 0.02);
    }

    #[test]
    fn grains_raining_onto_the_bed_and_a_diverged_one_are_left_out() {
        let d = 0.004;
        let (walls, mut p) = lattice(d);
        let orifice = (DVec3::ZERO, DVec3::Z, 2.0 * d);
        let bed = bed_packing(&walls, &p, orifice).expect("a bed to measure");
        // A few grains falling through the slabs above the bed, one far above, one
        // not finite.
        for k in 0..5 {
            let x = DVec3::new(0.0, 0.0, (31.5 + 3.0 * k as f64) * d);
            p.push(x, 0.5 * d, 2500.0, 0.4, 0, DVec3::ZERO, DVec3::ZERO);
        }
        let far = DVec3::new(0.0, 0.0, 1e6);
        p.push(far, 0.5 * d, 2500.0, 0.4, 0, DVec3::ZERO, DVec3::ZERO);
        let lost = DVec3::new(f64::NAN, 0.0, f64::INFINITY);
        p.push(lost, 0.5 * d, 2500.0, 0.4, 0, DVec3::ZERO, DVec3::ZERO);
        let phi = bed_packing(&walls, &p, orifice).expect("a bed to measure");
        assert!((phi - bed).abs() < 1e-12 * bed, "{phi} against {bed}");
    }

    #[test]
    fn without_a_silo_wall_or_a_deep_bed_nothing_is_measured() {
        let d = 0.004;
        let (walls, p) = lattice(d);
        let orifice = (DVec3::ZERO, DVec3::Z, 2.0 * d);
        assert!(bed_packing(&[], &p, orifice).is_none());
        // Orifice so wide that two of its diameters reach past the surface.
        assert!(bed_packing(&walls, &p, (DVec3::ZERO, DVec3::Z, 14.0 * d)).is_none());
    }
}
