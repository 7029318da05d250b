//! Particle and wall materials.

use serde::{Deserialize, Serialize};

/// A material as the scenario gives it. Elastic and dissipative properties are only
/// needed by the `material` contact model; the `hooke_history` model (LAMMPS parameters)
/// takes its stiffness, damping and friction from the contact table instead.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Name the particles and walls refer to.
    pub name: String,
    /// Density ρ (kg/m³): a disk's mass per unit thickness is ρπr², a sphere's 4/3 ρπr³.
    pub density: f64,
    /// Young's modulus Y (Pa).
    #[serde(default)]
    pub youngs: Option<f64>,
    /// Poisson's ratio ν (−); the shear modulus is G = Y / (2(1 + ν)).
    #[serde(default)]
    pub poisson: Option<f64>,
    /// Coefficient of restitution e in (0, 1] of a normal collision.
    #[serde(default)]
    pub restitution: Option<f64>,
    /// Coulomb friction coefficient μ ≥ 0.
    #[serde(default)]
    pub friction: Option<f64>,
    /// Moment of inertia as a fraction of m r²: by default a uniform disk's 0.5 in 2D, a
    /// uniform sphere's 0.4 in 3D; 0.4 in 2D reproduces LAMMPS `fix nve/sphere` without
    /// the `disc` keyword.
    #[serde(default = "default_inertia")]
    pub inertia_factor: f64,
}

fn default_inertia() -> f64 {
    crate::math::INERTIA_FACTOR
}

impl Material {
    /// Shear modulus G = Y / (2(1 + ν)), if Y and ν are given.
    pub fn shear_modulus(&self) -> Option<f64> {
        Some(self.youngs? / (2.0 * (1.0 + self.poisson?)))
    }
}
