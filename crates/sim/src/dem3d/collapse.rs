//! The collapse of a granular column, judged by its run-out against Lube et al.
//! (J. Fluid Mech. 508, 2004, axisymmetric columns): a column of radius R0 and height H0
//! held in a tube spreads, once the tube is gone, to a deposit of radius R∞ with
//! (R∞ − R0)/R0 ≈ 1.24 a for a = H0/R0 < 1.7 and ≈ 1.6 a^{1/2} beyond.
//!
//! The figures, all about the tube's axis: R0 is the tube's radius; H0 the height of the
//! column at the last history sample before the release, from the lowest sphere bottom
//! to the level below which 99 % of the sphere tops lie; R∞ at the end, the radius within
//! which 99 % of the spheres' outer edges lie. Lube et al. take the deposit's front,
//! where the continuous deposit ends; the 99 % radius is that front with the few grains
//! that roll off alone on the floor left out, which a small column has in proportion
//! more of than their columns of 10⁵–10⁷ grains.
//!
//! Beside R∞, as a figure only, the edge of the continuous deposit ([`super::deposit`]:
//! where the grains' azimuthally averaged coverage of the floor first falls below
//! [`deposit::COVERED`]), one reading of Lube et al.'s front. It does not replace R∞ in
//! the check: Lube et al.'s own definition could not be read, so the reading is
//! unverified, and it moves by more than the check's tolerance with its threshold
//! (VALIDATION.md, "Column collapse"). The outermost sphere edge is a figure too.

use super::deposit;
use super::scenario::{Scenario, WallSpec};
use super::Dem3;
use glam::DVec3;
use grains_core::input::InputError;
use grains_dem3d::{Particles, Setup, WallShape};
use serde::{Deserialize, Serialize};

/// The fraction of the spheres within the column's height and the deposit's radius.
pub const HOLDING: f64 = 0.99;

/// Lube et al.'s run-out (R∞ − R0)/R0 of a column of aspect ratio `a` = H0/R0.
pub fn lube(a: f64) -> f64 {
    if a < 1.7 {
        1.24 * a
    } else {
        1.6 * a.sqrt()
    }
}

/// A column's figures as the run goes: its height up to the release, its radius at the end.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunoutWatch {
    /// The tube (a cylinder wall's index).
    pub wall: usize,
    /// When the tube goes (s).
    pub release: f64,
    /// The tube's radius R0 (m).
    pub r0: f64,
    /// The column's height H0 at the last sample before the release (m).
    pub h0: f64,
}

/// The value below which `HOLDING` of `v` lie (NaN when empty).
fn holding(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let k = ((HOLDING * v.len() as f64).ceil() as usize).clamp(1, v.len());
    v[k - 1]
}

/// A point on the tube's axis and its unit direction.
fn axis(setup: &Setup, w: usize) -> Option<(DVec3, DVec3)> {
    match setup.walls.get(w)?.shape {
        WallShape::Cylinder { point, axis, .. } => {
            Some((point.into(), DVec3::from(axis).normalize()))
        }
        _ => None,
    }
}

impl RunoutWatch {
    /// Watches the column held by cylinder wall `wall`, released at `release`.
    pub fn new(sim: &Dem3, wall: usize, release: f64) -> Self {
        let r0 = match sim.setup.walls[wall].shape {
            WallShape::Cylinder { radius, .. } => radius,
            _ => f64::NAN,
        };
        RunoutWatch {
            wall,
            release,
            r0,
            h0: f64::NAN,
        }
    }

    /// Whether it samples at `time`: while the tube holds the column.
    pub fn wants(&self, time: f64) -> bool {
        time <= self.release
    }

    /// Takes one sample of every sphere, `p`: the column's height while the tube holds
    /// it.
    pub fn sample(&mut self, sim: &Dem3, p: &Particles) {
        if !self.wants(sim.state.time) {
            return;
        }
        let Some((c, _)) = axis(&sim.setup, self.wall) else {
            return;
        };
        let up = -sim.setup.gravity.normalize_or_zero();
        let h: Vec<f64> = (0..p.len()).map(|i| (p.pos[i] - c).dot(up)).collect();
        let base = (0..p.len())
            .map(|i| h[i] - p.radius[i])
            .fold(f64::INFINITY, f64::min);
        self.h0 = holding((0..p.len()).map(|i| h[i] + p.radius[i]).collect()) - base;
    }

    /// The deposit of the spheres `p` about the tube's axis ([`Deposit`]).
    pub fn deposit(&self, sim: &Dem3, p: &Particles) -> Deposit {
        let Some((c, u)) = axis(&sim.setup, self.wall) else {
            return Deposit::NAN;
        };
        let s: Vec<f64> = (0..p.len())
            .map(|i| {
                let d = p.pos[i] - c;
                (d - d.dot(u) * u).length()
            })
            .collect();
        let edges: Vec<f64> = (0..p.len()).map(|i| s[i] + p.radius[i]).collect();
        let front = edges.iter().copied().fold(f64::NAN, f64::max);
        // Rings one mean grain diameter wide.
        let width = 2.0 * p.radius.iter().sum::<f64>() / p.len() as f64;
        Deposit {
            edge: deposit::edge(&deposit::coverage(&s, &p.radius, width), width),
            r99: holding(edges),
            front,
        }
    }
}

/// A deposit's radii about the tube's axis (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Deposit {
    /// Where the continuous deposit ends ([`deposit::edge`]); a figure, not the check's.
    pub edge: f64,
    /// R∞, the check's: the radius within which [`HOLDING`] of the spheres' outer edges
    /// lie.
    pub r99: f64,
    /// The outermost sphere edge.
    pub front: f64,
}

impl Deposit {
    /// No deposit to measure.
    pub const NAN: Deposit = Deposit {
        edge: f64::NAN,
        r99: f64::NAN,
        front: f64::NAN,
    };
}

/// Checks a `runout` check's wall (`wall`, its index among the assembled walls): a
/// cylinder the scenario releases, along gravity.
pub fn validate(
    k: usize,
    s: &Scenario,
    setup: &Setup,
    wall: &str,
    w: usize,
) -> Result<(), InputError> {
    let released = s.walls.iter().any(
        |spec| matches!(spec, WallSpec::Cylinder { name, release: Some(_), .. } if name == wall),
    );
    if !released {
        return Err(InputError::new(
            format!("check[{k}].wall"),
            format!("\"{wall}\""),
            "must name a cylinder wall with a release time (the tube holding the column)",
        ));
    }
    let g = setup.gravity;
    let vertical = axis(setup, w).is_some_and(|(_, u)| u.cross(g).length() <= 1e-9 * g.length());
    if g == DVec3::ZERO || !vertical {
        return Err(InputError::new(
            format!("check[{k}].wall"),
            format!("\"{wall}\""),
            "its axis must lie along gravity (non-zero): a column stands on the floor",
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lube_laws_meet_near_their_change() {
        assert_eq!(lube(1.0), 1.24);
        assert!((lube(4.0) - 3.2).abs() < 1e-15);
        assert!((lube(1.69) - lube(1.71)).abs() < 0.03);
    }

    #[test]
    fn holding_takes_the_99_percent_value() {
        let v: Vec<f64> = (1..=200).map(f64::from).collect();
        assert_eq!(holding(v), 198.0);
        assert_eq!(holding(vec![3.0]), 3.0);
        assert!(holding(Vec::new()).is_nan());
    }
}
