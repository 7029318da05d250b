//! The read-only description of an MPM run: grid, method options, materials, bodies
//! (with their temperature histories), contact laws, walls, gravity and time step. Every
//! stage reads it; none writes it.

use crate::grid::Grid;
use crate::material::Material;
use crate::particles::Particles;
use crate::shape::ShapeFunction;
use crate::thermal::TemperatureHistory;
use glam::DVec2;
use grains_core::input::InputError;
use serde::{Deserialize, Serialize};

/// When the stress is updated within a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum UpdateScheme {
    /// Update stress first, from the interpolated (contact-corrected) grid velocity.
    Usf,
    /// Update stress last, from the grid velocity after integration (Sulsky 1994).
    Usl,
    /// Update stress on average (Nairn 2003): half the strain increment from the
    /// interpolated velocity before the forces, half from the updated velocity after.
    Usavg,
    /// Modified USL: re-map the updated particle momenta to the grid, correct contact
    /// again, and take the strain rate from that (Sulsky 1995).
    Musl,
}

impl UpdateScheme {
    /// The names accepted in a scenario.
    pub const NAMES: &'static str = "\"usf\", \"usl\", \"usavg\" or \"musl\"";
}

/// How a body moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Motion {
    /// Deformable, driven by stress, gravity and contact.
    Free,
    /// Rigid, with this prescribed velocity (m/s) whatever it touches.
    Prescribed(DVec2),
}

/// A body: one velocity field on the grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// Name (history columns `<name>_x`, ...).
    pub name: String,
    /// Index into [`Setup::materials`].
    pub material: usize,
    /// Free or prescribed motion.
    pub motion: Motion,
    /// Prescribed temperature (`None`: constant, no thermal strain).
    pub temperature: Option<TemperatureHistory>,
}

impl Body {
    /// A deformable body at constant temperature.
    pub fn free(name: impl Into<String>, material: usize) -> Self {
        Body {
            name: name.into(),
            material,
            motion: Motion::Free,
            temperature: None,
        }
    }
}

/// What happens where two bodies' velocity fields meet at a node.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "law", rename_all = "snake_case", deny_unknown_fields)]
pub enum ContactLaw {
    /// Coulomb friction: approaching fields lose their relative normal velocity, and
    /// tangential slip is resisted up to μ times the normal impulse (μ = 0: frictionless).
    Coulomb {
        /// Friction coefficient μ ≥ 0.
        mu: f64,
    },
    /// One velocity field: the bodies move together (bonded, no slip, no separation).
    NoSlip,
    /// Bonded up to a normal traction `strength`, then Coulomb with `mu` (Bardenhagen et
    /// al. 1998): where the interface's normal traction is at most the bond it moves as
    /// one body; where it exceeds the bond, the bond there fails for good (the points
    /// remember it); a failed interface slides with friction μ when approaching or in
    /// compression and separates freely otherwise. See [`crate::bond`].
    Bonded {
        /// Bond strength (Pa, normal traction in tension), ≥ 0. The bodies' points carry
        /// it from the start ([`crate::State::new`]).
        strength: f64,
        /// Friction coefficient once debonded, ≥ 0.
        #[serde(default)]
        mu: f64,
    },
}

/// Contact laws for every pair of bodies: a default and per-pair overrides.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactTable {
    laws: Vec<ContactLaw>,
    index: Vec<u8>,
    bodies: usize,
}

impl ContactTable {
    /// Every pair of `bodies` bodies uses `default`.
    pub fn new(bodies: usize, default: ContactLaw) -> Self {
        ContactTable {
            laws: vec![default],
            index: vec![0; bodies * bodies],
            bodies,
        }
    }

    /// Sets the law between bodies `a` and `b` (both orders).
    pub fn set(&mut self, a: usize, b: usize, law: ContactLaw) {
        let k = match self.laws.iter().position(|l| *l == law) {
            Some(k) => k,
            None => {
                self.laws.push(law);
                self.laws.len() - 1
            }
        };
        self.index[a * self.bodies + b] = k as u8;
        self.index[b * self.bodies + a] = k as u8;
    }

    /// The law between `a` and `b`.
    #[inline]
    pub fn get(&self, a: usize, b: usize) -> ContactLaw {
        self.laws[self.index[a * self.bodies + b] as usize]
    }

    /// Distinct laws in use (at most 255 kept apart).
    pub fn distinct(&self) -> usize {
        self.laws.len()
    }

    /// The distinct laws.
    pub fn laws(&self) -> &[ContactLaw] {
        &self.laws
    }

    /// The strongest bond body `b` has with any other body (0: none).
    pub fn bond_of(&self, b: usize) -> f64 {
        (0..self.bodies)
            .filter(|&c| c != b)
            .map(|c| match self.get(b, c) {
                ContactLaw::Bonded { strength, .. } => strength,
                _ => 0.0,
            })
            .fold(0.0, f64::max)
    }
}

/// The four domain edges, in the order of [`Setup::walls`].
pub const SIDES: [&str; 4] = ["left", "right", "bottom", "top"];

/// Everything the stages read and never write.
#[derive(Clone, Debug)]
pub struct Setup {
    /// Background grid.
    pub grid: Grid,
    /// Shape function.
    pub shape: ShapeFunction,
    /// GIMP particle half-width in grid units (½ · lattice pitch / h).
    pub half_width: f64,
    /// Stress update position.
    pub scheme: UpdateScheme,
    /// FLIP fraction α of the particle velocity update: v = α·FLIP + (1 − α)·PIC.
    pub flip: f64,
    /// Whether the first contact correction (on the interpolated momenta) also reaches
    /// the particles' velocities; the second (after integration) always does.
    pub pass1_to_particles: bool,
    /// Materials.
    pub materials: Vec<Material>,
    /// Bodies (at most 65535).
    pub bodies: Vec<Body>,
    /// Contact law per pair of bodies.
    pub contact: ContactTable,
    /// How contact is resolved where more than two bodies (or a rigid body and another)
    /// meet at a node.
    pub crowd: crate::contact::Crowd,
    /// Separation test between bodies (Nairn's position method): a node's fields are
    /// only corrected where the bodies' material centroids there are at most this far
    /// apart along the normal (m); `None`: approach alone decides.
    /// See [`crate::contact::touching_separation`].
    pub separation: Option<f64>,
    /// Domain edges that are rigid walls, with their friction μ (`None`: open edge;
    /// a particle that leaves the grid stops the run). Order: left, right, bottom, top.
    pub walls: [Option<f64>; 4],
    /// Gravitational acceleration (m/s²).
    pub gravity: DVec2,
    /// Keep the energy ledger of contact: the work the corrections do on the points, by
    /// kind ([`crate::Touch::points`]); costs a little in the particle update.
    pub ledger: bool,
}

fn positive(key: String, v: f64) -> Result<(), InputError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(InputError::new(key, v, "must be a finite number > 0"))
    }
}

impl Setup {
    /// Checks every value a stage relies on; the caller has validated names and
    /// geometry.
    pub fn validate(&self) -> Result<(), InputError> {
        positive("grid.cell_size".into(), self.grid.h)?;
        if self.grid.cells[0] < 2 || self.grid.cells[1] < 2 {
            return Err(InputError::new(
                "grid.cells",
                format!("{:?}", self.grid.cells),
                "need at least 2 cells along x and y",
            ));
        }
        if !(self.half_width > 0.0 && self.half_width <= 0.5) {
            return Err(InputError::new(
                "grid.particles_per_cell",
                self.half_width,
                "the particle half-width must be in (0, ½] cell",
            ));
        }
        if !(self.flip.is_finite() && (0.0..=1.0).contains(&self.flip)) {
            return Err(InputError::new(
                "method.flip",
                self.flip,
                "must be in [0, 1]",
            ));
        }
        for (k, m) in self.materials.iter().enumerate() {
            m.validate(&format!("material[{k}]"))?;
        }
        if self.bodies.is_empty() || self.bodies.len() > u16::MAX as usize {
            return Err(InputError::new(
                "body",
                self.bodies.len(),
                "need between 1 and 65535 bodies",
            ));
        }
        for (k, b) in self.bodies.iter().enumerate() {
            if b.material >= self.materials.len() {
                return Err(InputError::new(
                    format!("body[{k}].material"),
                    b.material,
                    "unknown material",
                ));
            }
            if let Motion::Prescribed(v) = b.motion {
                if !v.is_finite() {
                    return Err(InputError::new(
                        format!("body[{k}].velocity"),
                        format!("{v:?}"),
                        "must be finite",
                    ));
                }
            }
            if let Some(h) = &b.temperature {
                h.validate(&format!("body[{k}].temperature"))?;
            }
        }
        for law in self.contact.laws() {
            match *law {
                ContactLaw::Coulomb { mu } if !(mu.is_finite() && mu >= 0.0) => {
                    return Err(InputError::new(
                        "contact.mu",
                        mu,
                        "must be a finite number >= 0",
                    ));
                }
                ContactLaw::Bonded { strength, mu } => {
                    if !(strength.is_finite() && strength >= 0.0) {
                        return Err(InputError::new(
                            "contact.strength",
                            strength,
                            "must be a finite number >= 0",
                        ));
                    }
                    if !(mu.is_finite() && mu >= 0.0) {
                        return Err(InputError::new(
                            "contact.mu",
                            mu,
                            "must be a finite number >= 0",
                        ));
                    }
                    if self.bodies.len() < 2 {
                        return Err(InputError::new(
                            "contact.strength",
                            strength,
                            "a bond needs two bodies; there is only one",
                        ));
                    }
                }
                _ => {}
            }
        }
        for (k, w) in self.walls.iter().enumerate() {
            if let Some(mu) = w {
                if !(mu.is_finite() && *mu >= 0.0) {
                    return Err(InputError::new(
                        format!("walls.{}.mu", SIDES[k]),
                        mu,
                        "must be a finite number >= 0",
                    ));
                }
            }
        }
        if self.grid.periodic_y {
            for side in [2, 3] {
                if let Some(mu) = self.walls[side] {
                    return Err(InputError::new(
                        format!("walls.{}", SIDES[side]),
                        format!("{{ mu = {mu} }}"),
                        "the grid is periodic along y (grid.periodic_y): no wall at the bottom or top",
                    ));
                }
            }
            if self.gravity.y != 0.0 {
                return Err(InputError::new(
                    "gravity",
                    format!("{:?}", self.gravity.to_array()),
                    "no y component along a periodic y (grid.periodic_y): the potential energy would jump at the seam",
                ));
            }
        }
        if !self.gravity.is_finite() {
            return Err(InputError::new(
                "gravity",
                format!("{:?}", self.gravity),
                "must be finite",
            ));
        }
        Ok(())
    }

    /// True if some node can hold two bodies' fields, i.e. contact must be resolved.
    pub fn multi_body(&self) -> bool {
        self.bodies.len() > 1
    }

    /// True if some pair of bodies is bonded.
    pub fn bonds(&self) -> bool {
        self.multi_body()
            && self
                .contact
                .laws()
                .iter()
                .any(|l| matches!(l, ContactLaw::Bonded { .. }))
    }

    /// Maxwell branches each point must store: the most any body's material has.
    pub fn branch_width(&self) -> usize {
        self.bodies
            .iter()
            .map(|b| self.materials[b.material].branches())
            .max()
            .unwrap_or(0)
    }

    /// Gives every point the bond strength of its body ([`ContactTable::bond_of`]) and
    /// the storage its material's state needs.
    pub fn prepare_points(&self, p: &mut Particles) {
        p.set_branch_width(self.branch_width());
        let bond: Vec<f64> = (0..self.bodies.len())
            .map(|b| self.contact.bond_of(b))
            .collect();
        for i in 0..p.len() {
            p.bond[i] = bond[p.body[i] as usize];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::PronyTerm;

    fn two_bodies(law: ContactLaw) -> Setup {
        let m = Material::LinearElastic {
            name: "m".into(),
            density: 1.0,
            bulk: 1.0,
            shear: 0.5,
            expansion: 0.0,
        };
        Setup {
            grid: Grid {
                lo: DVec2::ZERO,
                h: 0.1,
                cells: [10, 10],
                periodic_y: false,
            },
            shape: ShapeFunction::Gimp,
            half_width: 0.25,
            scheme: UpdateScheme::Usf,
            flip: 1.0,
            pass1_to_particles: true,
            materials: vec![m],
            bodies: vec![Body::free("a", 0), Body::free("b", 0)],
            contact: ContactTable::new(2, law),
            crowd: Default::default(),
            separation: None,
            walls: [None; 4],
            gravity: DVec2::ZERO,
            ledger: false,
        }
    }

    #[test]
    fn bad_input_names_key_and_value() {
        let bonded = |strength, mu| ContactLaw::Bonded { strength, mu };
        assert!(two_bodies(bonded(1.0, 0.3)).validate().is_ok());
        let e = two_bodies(bonded(-1.0, 0.3)).validate().unwrap_err();
        assert_eq!(
            (e.key.as_str(), e.value.as_str()),
            ("contact.strength", "-1")
        );
        let e = two_bodies(bonded(1.0, f64::NAN)).validate().unwrap_err();
        assert_eq!(e.key, "contact.mu");
        // A bond with no partner.
        let mut s = two_bodies(bonded(2.0, 0.0));
        s.bodies.pop();
        s.contact = ContactTable::new(1, bonded(2.0, 0.0));
        let e = s.validate().unwrap_err();
        assert_eq!(e.key, "contact.strength");
        assert!(e.allowed.contains("two bodies"), "{e}");
        // Temperature table out of order.
        let mut s = two_bodies(ContactLaw::NoSlip);
        s.bodies[1].temperature = Some(TemperatureHistory::Table {
            points: vec![[0.0, 300.0], [1.0, 310.0], [0.5, 320.0]],
        });
        let e = s.validate().unwrap_err();
        assert_eq!(e.key, "body[1].temperature.points[2]");
        assert_eq!(e.value, "[0.5, 320.0]");
        // A material's own parameters.
        let mut s = two_bodies(ContactLaw::NoSlip);
        s.materials[0] = Material::Maxwell {
            name: "binder".into(),
            density: 1.0,
            bulk: 1.0,
            shear: 0.0,
            prony: vec![PronyTerm {
                shear: 1.0,
                time: f64::INFINITY,
            }],
            expansion: 0.0,
        };
        let e = s.validate().unwrap_err();
        assert_eq!(e.key, "material[0].prony[0].time");
        assert_eq!(
            e.to_string(),
            "material[0].prony[0].time = inf: must be a finite number > 0"
        );
    }

    #[test]
    fn points_take_their_bodies_bond_and_branch_storage() {
        let mut s = two_bodies(ContactLaw::Coulomb { mu: 0.1 });
        s.materials.push(Material::Maxwell {
            name: "binder".into(),
            density: 1.0,
            bulk: 1.0,
            shear: 0.0,
            prony: vec![
                PronyTerm {
                    shear: 1.0,
                    time: 1.0
                };
                3
            ],
            expansion: 0.0,
        });
        s.bodies.push(Body::free("binder", 1));
        s.contact = ContactTable::new(3, ContactLaw::Coulomb { mu: 0.1 });
        s.contact.set(
            0,
            2,
            ContactLaw::Bonded {
                strength: 5.0,
                mu: 0.3,
            },
        );
        s.contact.set(
            1,
            2,
            ContactLaw::Bonded {
                strength: 7.0,
                mu: 0.3,
            },
        );
        let mut p = Particles::default();
        for b in [0, 1, 2, 2] {
            p.push(b, 1.0, 1.0, DVec2::splat(0.5), DVec2::ZERO);
        }
        s.prepare_points(&mut p);
        assert_eq!(p.bond, vec![5.0, 7.0, 7.0, 7.0]);
        assert_eq!(p.branch_width, 3);
        assert_eq!(p.branches.len(), 12);
        assert!(s.bonds());
    }
}
