//! The read-only description of a charge run: explosive, burn, viscosity, strength,
//! damping and the time-step safety factor.

use crate::explosive::Explosive;
use glam::DVec2;
use grains_core::input::{non_negative, positive, shown, InputError};
use serde::{Deserialize, Serialize};

/// Programmed burn (xue-2019 Eqs. A1–A2, physics.md §1.3).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Burn {
    /// Detonation point x_d (m); default: the charge centre.
    #[serde(default)]
    pub point: Option<[f64; 2]>,
    /// Detonation time t0 (s).
    #[serde(default)]
    pub time: f64,
    /// Burn width: d_eff = width × A_e/L_max (element area over its longest edge, the
    /// 2D analogue of LS-DYNA's v_e/A_max), so the time-lit fraction grows by Δt·D/d_eff
    /// per step (Eq. A2); 1.5 as in LS-DYNA and OpenRadioss.
    #[serde(default = "default_width")]
    pub width: f64,
    /// Also burn by compression: λ ≥ (1 − V)/(1 − V_CJ) (the "beta" burn).
    #[serde(default = "yes")]
    pub compression: bool,
}

fn default_width() -> f64 {
    1.5
}
fn yes() -> bool {
    true
}

impl Default for Burn {
    fn default() -> Self {
        Burn {
            point: None,
            time: 0.0,
            width: default_width(),
            compression: true,
        }
    }
}

/// Artificial bulk viscosity q = ρ(c_q L² ε̇_v² − c_l L c ε̇_v) in compression (ε̇_v < 0),
/// L = the element size; LS-DYNA's defaults.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Viscosity {
    /// Linear coefficient c_l.
    #[serde(default = "default_linear")]
    pub linear: f64,
    /// Quadratic coefficient c_q.
    #[serde(default = "default_quadratic")]
    pub quadratic: f64,
}

fn default_linear() -> f64 {
    0.06
}
fn default_quadratic() -> f64 {
    1.5
}

impl Default for Viscosity {
    fn default() -> Self {
        Viscosity {
            linear: default_linear(),
            quadratic: default_quadratic(),
        }
    }
}

/// Deviatoric stress: hypo-elastic (Jaumann rate) with a von Mises cap. By default it is
/// the unreacted explosive's and scales with 1 − λ, so the products carry none; with
/// `products = true` every element keeps it, as in xue-2019 Eq. A4, where the
/// elements' "deformation force" acts beside the detonation pressure — it also keeps
/// the Lagrangian mesh from shearing into slivers.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Strength {
    /// Shear modulus G (Pa).
    pub shear_modulus: f64,
    /// Yield stress Y (Pa).
    pub yield_stress: f64,
    /// Keep the deviatoric stress in the products too.
    #[serde(default)]
    pub products: bool,
}

/// Everything the charge's stages read.
#[derive(Clone, Debug, PartialEq)]
pub struct FemSetup {
    /// The explosive.
    pub explosive: Explosive,
    /// Detonation point (m), resolved.
    pub det_point: DVec2,
    /// Burn settings.
    pub burn: Burn,
    /// Artificial viscosity.
    pub viscosity: Viscosity,
    /// Deviatoric stress, if any.
    pub strength: Option<Strength>,
    /// Global non-viscous damping ratio α of xue-2019 Eq. A5 (0 = none).
    pub damping: f64,
    /// Fraction of the stable time step used.
    pub safety: f64,
}

impl FemSetup {
    /// Validates the settings for a charge of `radius` about `centre`.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        explosive: Explosive,
        explosive_key: &str,
        centre: DVec2,
        radius: f64,
        burn: Burn,
        viscosity: Viscosity,
        strength: Option<Strength>,
        damping: f64,
        safety: f64,
    ) -> Result<Self, InputError> {
        explosive.validate(explosive_key)?;
        let det_point = burn.point.map_or(centre, DVec2::from);
        if !det_point.is_finite() || (det_point - centre).length() > radius * (1.0 + 1e-12) {
            return Err(InputError::new(
                "charge.burn.point",
                format!("{:?}", burn.point.unwrap_or_default()),
                format!(
                    "must lie inside the charge (centre {:?}, radius {} m)",
                    centre.to_array(),
                    shown(radius)
                ),
            ));
        }
        if !burn.time.is_finite() {
            return Err(InputError::new(
                "charge.burn.time",
                shown(burn.time),
                "must be finite",
            ));
        }
        positive("charge.burn.width", burn.width)?;
        non_negative("charge.viscosity.linear", viscosity.linear)?;
        non_negative("charge.viscosity.quadratic", viscosity.quadratic)?;
        if let Some(s) = strength {
            positive("charge.strength.shear_modulus", s.shear_modulus)?;
            positive("charge.strength.yield_stress", s.yield_stress)?;
        }
        if !(damping.is_finite() && (0.0..1.0).contains(&damping)) {
            return Err(InputError::new(
                "charge.damping",
                shown(damping),
                "must be in [0, 1)",
            ));
        }
        if !(safety.is_finite() && safety > 0.0 && safety <= 1.0) {
            return Err(InputError::new(
                "run.safety",
                shown(safety),
                "must be in (0, 1]",
            ));
        }
        Ok(FemSetup {
            explosive,
            det_point,
            burn,
            viscosity,
            strength,
            damping,
            safety,
        })
    }
}
