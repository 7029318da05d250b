//! What the contact corrections exchange, summed step by step: the forces rigid bodies
//! exert on the material (their reactions), the work they do, the energy the contacts
//! take out (friction, bonds), how far the rigid bodies moved, and how far the momentum
//! the free bodies give one another is from summing to zero.
//!
//! The energy a kind of contact takes out is what the rigid bodies put in through it
//! (Σ Δp·v_rigid over its corrections) less the work its corrections did on the free
//! bodies' grid fields, Σ m v̄·δv, with v̄ the midpoint of the velocity change the
//! particles take from the grid in the step: between two free bodies the latter is
//! negative, and minus it is the energy lost. With the same v̄, the grid fields' kinetic
//! energy change is exactly that work plus the internal forces' (whose work the stress
//! update stores as strain energy, plastic work or viscous loss); the points gain a
//! little less than the grid (the FLIP projection of a change that jumps at a contact
//! smooths it): that difference is the `transfer` line of the ledger. The per-correction
//! alternatives both fail: each correction's own kinetic energy loss counts again and
//! again the approach that FLIP points carry back to the grid each step (2.5 times the
//! boundary work in the dry cell), and the work on the points at their own velocities
//! splits the kinetic energy change arbitrarily between contact and internal forces (a
//! frictionless fixed wall seemed to do positive work on a bouncing disk).

use glam::DVec2;
use grains_mpm::contact::{HELD, SLIDE};
use grains_mpm::{Motion, Setup, Touch};

/// The running sums of a run.
#[derive(Clone, Debug, Default)]
pub struct Exchange {
    /// Per body, the momentum received from rigid bodies since the last sample (a rigid
    /// body: what it received from the free bodies).
    interval: Vec<DVec2>,
    /// Time of the last sample (s).
    since: f64,
    /// Energy taken out by Coulomb contacts and walls (J per unit thickness).
    pub friction: f64,
    /// Energy taken out where bonds hold or fail (and `no_slip` contacts).
    pub bond: f64,
    /// Energy the transfer from the grid to the points loses (numerical: the FLIP
    /// projection of the grid's velocity change).
    pub transfer: f64,
    /// Work done by the rigid bodies on the free ones.
    pub work: f64,
    /// Per body, the work it did (rigid bodies).
    pub work_by: Vec<f64>,
    /// Σ over steps of the momentum the free bodies' fields received from one another:
    /// zero when every exchange is equal and opposite.
    pub imbalance: DVec2,
    /// Σ over steps of |that step's imbalance|.
    pub imbalance_abs: f64,
    /// Σ over steps of |momentum the free bodies received from rigid bodies|.
    pub boundary_impulse: f64,
    /// Per body, the displacement by its prescribed velocity (rigid bodies, m).
    pub displacement: Vec<DVec2>,
}

impl Exchange {
    /// Nothing exchanged yet, for `bodies` bodies.
    pub fn new(bodies: usize) -> Self {
        Exchange {
            interval: vec![DVec2::ZERO; bodies],
            work_by: vec![0.0; bodies],
            displacement: vec![DVec2::ZERO; bodies],
            ..Default::default()
        }
    }

    /// Adds a step of length `dt` whose corrections are `touch` (bodies' motions from
    /// `setup`, as they were during the step).
    pub fn step(&mut self, setup: &Setup, touch: &[Touch], dt: f64) {
        let (mut among, mut from_rigid) = (DVec2::ZERO, DVec2::ZERO);
        for (b, t) in touch.iter().enumerate() {
            self.friction += t.work[SLIDE] - t.grid[SLIDE];
            self.bond += t.work[HELD] - t.grid[HELD];
            self.transfer += t.ke_grid - t.ke_points;
            let w = t.work[SLIDE] + t.work[HELD];
            self.work += w;
            self.work_by[b] += w;
            match setup.bodies[b].motion {
                Motion::Prescribed(v) => {
                    self.interval[b] += t.from_rigid;
                    self.displacement[b] += v * dt;
                }
                Motion::Free => {
                    among += t.from_free;
                    from_rigid += t.from_rigid;
                }
            }
        }
        self.imbalance += among;
        self.imbalance_abs += among.length();
        self.boundary_impulse += from_rigid.length();
    }

    /// The mean force each rigid body exerted on the material since the last sample
    /// (zero for free bodies; N per unit thickness), and a new interval from `t`.
    pub fn forces(&mut self, t: f64) -> Vec<DVec2> {
        let span = t - self.since;
        self.since = t;
        self.interval
            .iter_mut()
            .map(|i| {
                let f = if span > 0.0 { -*i / span } else { DVec2::ZERO };
                *i = DVec2::ZERO;
                f
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use grains_mpm::{Body, ContactLaw, ContactTable, Grid, Material, ShapeFunction};

    #[test]
    fn forces_are_interval_means_and_imbalance_sums_free_exchanges() {
        let m = Material::LinearElastic {
            name: "m".into(),
            density: 1.0,
            bulk: 1.0,
            shear: 0.5,
            expansion: 0.0,
        };
        let mut wall = Body::free("wall", 0);
        wall.motion = Motion::Prescribed(DVec2::new(0.0, 2.0));
        let setup = Setup {
            grid: Grid {
                lo: DVec2::ZERO,
                h: 1.0,
                cells: [4, 4],
                periodic_y: false,
            },
            shape: ShapeFunction::Gimp,
            half_width: 0.25,
            scheme: grains_mpm::UpdateScheme::Usf,
            flip: 1.0,
            pass1_to_particles: true,
            materials: vec![m],
            bodies: vec![wall, Body::free("a", 0), Body::free("b", 0)],
            contact: ContactTable::new(3, ContactLaw::Coulomb { mu: 0.0 }),
            crowd: Default::default(),
            separation: None,
            walls: [None; 4],
            gravity: DVec2::ZERO,
            ledger: false,
        };
        let mut x = Exchange::new(3);
        let push = Touch {
            from_rigid: DVec2::new(-1.0, 0.0),
            work: [0.5, 0.0],
            ..Default::default()
        };
        let a = Touch {
            from_rigid: DVec2::new(1.0, 0.0),
            from_free: DVec2::new(0.0, 0.25),
            grid: [0.4, 0.0],
            ..Default::default()
        };
        let b = Touch {
            from_free: DVec2::new(0.0, -0.25),
            ..Default::default()
        };
        for _ in 0..4 {
            x.step(&setup, &[push, a, b], 0.5);
        }
        let f = x.forces(2.0);
        assert_eq!(f[0], DVec2::new(2.0, 0.0));
        assert_eq!(x.forces(3.0)[0], DVec2::ZERO);
        assert_eq!(x.displacement[0], DVec2::new(0.0, 4.0));
        assert_eq!(x.work, 2.0);
        assert!((x.friction - 0.4).abs() < 1e-15);
        assert_eq!(x.imbalance, DVec2::ZERO);
        assert_eq!(x.boundary_impulse, 4.0);
    }
}
