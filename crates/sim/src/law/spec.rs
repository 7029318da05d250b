//! The `[contact]` table as the scenario writes it, with LAMMPS's keywords.

use super::engine::granular::{Damping, Tangential};
use super::engine::ContactModel;
use serde::{Deserialize, Serialize};

/// Which law a `[contact]` table (or one of its `[[contact.pair]]`) gives.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LawModel {
    /// LAMMPS `gran/hooke/history kn kt γn γt μ` (the linear law, as in 2D).
    HookeHistory,
    /// LAMMPS `pair_style granular` with the keywords below.
    Granular,
    /// xue-2019 App. B, the stiffnesses, restitution and friction from the materials
    /// (2D only, the default there; `limit_damping` its one key).
    Material,
}

/// The normal model of the granular law, spelled as LAMMPS spells it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum NormalSpec {
    /// `hooke k_n damp`.
    #[serde(rename = "hooke")]
    Hooke,
    /// `hertz/material E damp ν`, E and ν from the materials.
    #[serde(rename = "hertz/material")]
    HertzMaterial,
}

/// `[contact]`: a contact law with LAMMPS's keywords. The whole table applies to every
/// pair; a `[[contact.pair]]` (with `materials`) gives one pair its own law.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LawSpec {
    /// `"hooke_history"`, `"granular"` or (2D) `"material"`.
    pub model: Option<LawModel>,
    /// The pair this law is for (only in `[[contact.pair]]`).
    #[serde(default)]
    pub materials: Option<[String; 2]>,
    /// hooke_history: normal stiffness (N/m); granular `hooke`: k_n.
    #[serde(default)]
    pub kn: Option<f64>,
    /// Tangential stiffness (N/m; `mindlin`: the factor of a, Pa, default 8G*).
    #[serde(default)]
    pub kt: Option<f64>,
    /// hooke_history: normal damping rate γn (1/s).
    #[serde(default)]
    pub gamma_n: Option<f64>,
    /// hooke_history: tangential damping rate γt (1/s).
    #[serde(default)]
    pub gamma_t: Option<f64>,
    /// Friction coefficient (granular: default the materials' `friction`, mixed as the
    /// geometric mean).
    #[serde(default)]
    pub mu: Option<f64>,
    /// granular: normal model.
    #[serde(default)]
    pub normal: Option<NormalSpec>,
    /// granular: damping model (`tsuji`, `restitution` (α solved for e), `viscoelastic`,
    /// `velocity`, `mass_velocity`).
    #[serde(default)]
    pub damping: Option<Damping>,
    /// granular: η₀ of `velocity`, `mass_velocity`, `viscoelastic`.
    #[serde(default)]
    pub damp: Option<f64>,
    /// granular: restitution of `tsuji` and `restitution` (default the materials',
    /// mixed as the geometric mean).
    #[serde(default)]
    pub restitution: Option<f64>,
    /// granular: tangential model.
    #[serde(default)]
    pub tangential: Option<Tangential>,
    /// granular: tangential damping over normal damping (default 1).
    #[serde(default)]
    pub x_gamma_t: Option<f64>,
    /// granular: `"sds"` rolling resistance with `kr`, `gamma_r`, `mu_r`.
    #[serde(default)]
    pub rolling: Option<String>,
    /// Rolling stiffness k_r (N/m).
    #[serde(default)]
    pub kr: Option<f64>,
    /// Rolling damping γ_r (N s/m).
    #[serde(default)]
    pub gamma_r: Option<f64>,
    /// Rolling friction μ_r.
    #[serde(default)]
    pub mu_r: Option<f64>,
    /// granular: `"marshall"` twisting resistance.
    #[serde(default)]
    pub twisting: Option<String>,
    /// Clamp the normal force at zero.
    #[serde(default)]
    pub limit_damping: bool,
    /// Pairs with their own law.
    #[serde(default)]
    pub pair: Vec<LawSpec>,
}

/// The table of a scenario that gives none: the material route (2D's default).
pub fn material_law() -> LawSpec {
    LawSpec {
        model: Some(LawModel::Material),
        ..LawSpec::default()
    }
}

/// The table that gives the engine's linear model `m` (scenarios that embed a DEM one
/// write the engine's model).
impl From<&ContactModel> for LawSpec {
    fn from(m: &ContactModel) -> Self {
        match *m {
            ContactModel::Material { limit_damping } => LawSpec {
                limit_damping,
                ..material_law()
            },
            ContactModel::HookeHistory {
                kn,
                kt,
                gamma_n,
                gamma_t,
                mu,
                limit_damping,
            } => LawSpec {
                model: Some(LawModel::HookeHistory),
                kn: Some(kn),
                kt: Some(kt),
                gamma_n: Some(gamma_n),
                gamma_t: Some(gamma_t),
                mu: Some(mu),
                limit_damping,
                ..LawSpec::default()
            },
        }
    }
}
