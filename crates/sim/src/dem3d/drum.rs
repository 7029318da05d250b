//! What a rotating drum is judged by, sampled at history times once the bed has spun
//! up: the dynamic angle of repose of its free surface, and the torque the grains put on
//! the drum about its axis against the moment of their weight about it (equal when the
//! bed's angular momentum is steady: a check of the turning wall's torque).
//!
//! The surface: in the cross-section (coordinates across the axis, horizontal h and
//! vertical v), the grains are binned by h in columns one mean diameter wide over the
//! middle 70 % of the drum's width, away from the wall; each column's top is its highest
//! grain's top (v + r), and a least-squares line through the tops gives the angle.

use super::Dem3;
use glam::DVec3;
use grains_dem3d::{Particles, WallShape};
use serde::{Deserialize, Serialize};

/// Running means of a drum's figures from time `after` on.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct DrumWatch {
    /// The drum (a cylinder wall's index).
    pub wall: usize,
    /// Start of the averaging (s).
    pub after: f64,
    angle: (f64, u32),
    torque: f64,
    moment: f64,
}

impl DrumWatch {
    /// Averages over samples from `after` on, of the cylinder wall `wall`.
    pub fn new(wall: usize, after: f64) -> Self {
        DrumWatch {
            wall,
            after,
            angle: (0.0, 0),
            torque: 0.0,
            moment: 0.0,
        }
    }

    /// Whether it samples at `time`.
    pub fn wants(&self, time: f64) -> bool {
        time >= self.after
    }

    /// Takes one sample of every sphere, `p` (in ascending id: the sums' order).
    pub fn sample(&mut self, sim: &Dem3, p: &Particles) {
        if !self.wants(sim.state.time) {
            return;
        }
        let Some((c, u, radius)) = cylinder(sim, self.wall) else {
            return;
        };
        if let Some(a) = surface_angle(sim, p, c, u, radius) {
            self.angle.0 += a;
            self.angle.1 += 1;
        }
        let g = sim.setup.gravity;
        self.moment += (0..p.len())
            .map(|i| (p.pos[i] - c).cross(p.mass(i) * g).dot(u))
            .sum::<f64>();
        self.torque += sim.state.wall_loads[self.wall].torque.dot(u);
    }

    /// Mean surface angle (degrees), NaN before any sample.
    pub fn angle(&self) -> f64 {
        self.angle.0 / self.angle.1 as f64
    }

    /// Mean torque of the grains on the drum about its axis over the mean moment of
    /// their weight about it (1 when steady), NaN before any sample.
    pub fn torque_over_moment(&self) -> f64 {
        self.torque / self.moment
    }
}

/// A point on the axis, its unit direction and the radius of cylinder wall `w`.
fn cylinder(sim: &Dem3, w: usize) -> Option<(DVec3, DVec3, f64)> {
    match sim.setup.walls.get(w)?.shape {
        WallShape::Cylinder {
            point,
            axis,
            radius,
            ..
        } => Some((point.into(), DVec3::from(axis).normalize(), radius)),
        _ => None,
    }
}

/// The free surface's angle to the horizontal (degrees) of the spheres `p` in the drum
/// about `c` along `u`, or None with fewer than three columns of grains.
fn surface_angle(sim: &Dem3, p: &Particles, c: DVec3, u: DVec3, radius: f64) -> Option<f64> {
    let up = -sim.setup.gravity.normalize_or_zero();
    let across = u.cross(up).normalize_or_zero();
    let n = p.len();
    if n == 0 || across == DVec3::ZERO {
        return None;
    }
    let width = 2.0 * p.radius.iter().sum::<f64>() / n as f64;
    let half = 0.7 * radius;
    let bins = (2.0 * half / width).floor() as usize;
    let mut top = vec![f64::NEG_INFINITY; bins];
    for i in 0..n {
        let d = p.pos[i] - c;
        let h = d.dot(across) + half;
        if h >= 0.0 && h < bins as f64 * width {
            let b = (h / width) as usize;
            top[b] = top[b].max(d.dot(up) + p.radius[i]);
        }
    }
    let pts: Vec<(f64, f64)> = top
        .iter()
        .enumerate()
        .filter(|(_, t)| t.is_finite())
        .map(|(b, &t)| ((b as f64 + 0.5) * width, t))
        .collect();
    if pts.len() < 3 {
        return None;
    }
    let m = pts.len() as f64;
    let (sx, sy) = pts.iter().fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
    let (mx, my) = (sx / m, sy / m);
    let (sxy, sxx) = pts.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    Some((sxy / sxx).atan().abs().to_degrees())
}
