//! The read-only description of an MPM run: grid, method options, materials, bodies,
//! contact laws, walls, gravity and time step. Every stage reads it; none writes it.

use crate::grid::Grid;
use crate::material::Material;
use crate::shape::ShapeFunction;
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
            positive(format!("material[{k}].density"), m.density())?;
            let (bulk, shear) = m.moduli();
            positive(format!("material[{k}].bulk"), bulk)?;
            positive(format!("material[{k}].shear"), shear)?;
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
}
