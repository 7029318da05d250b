//! Constitutive models, chosen per body: hypo-elastic linear elasticity, compressible
//! Neo-Hookean hyperelasticity, J2 elastic-plastic with linear isotropic hardening, and a
//! generalized Maxwell (Prony series) viscoelastic solid. The rate models rotate their
//! stresses by the Hughes–Winget increment, so rigid rotation leaves them unchanged. Plane
//! strain: F_zz = 1, D_zz = 0, and σ_zz is carried because pressure, yield and energy need
//! it. The rate models also take an isotropic thermal strain α ΔT from the body's
//! temperature history. How a step updates a point is in [`crate::models`].

use crate::models::{ElasticStep, J2Step, MaxwellStep, NeoHookeanStep, Prepared};
use crate::thermal::Thermal;
use glam::DMat2;
use grains_core::input::InputError;
use serde::{Deserialize, Serialize};

/// A material, chosen per body in the scenario (`model = ...`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "model", rename_all = "snake_case", deny_unknown_fields)]
pub enum Material {
    /// Small-strain isotropic elasticity in rate form, σ̇ = λ tr(D) I + 2G D − 3Kα Ṫ I,
    /// with the stress rotated by the Hughes–Winget increment so rigid rotation leaves it
    /// unchanged.
    LinearElastic {
        /// Name bodies refer to.
        name: String,
        /// Density ρ (kg/m³).
        density: f64,
        /// Bulk modulus K (Pa).
        bulk: f64,
        /// Shear modulus G (Pa).
        shear: f64,
        /// Linear thermal expansion coefficient α (per unit of temperature), ≥ 0.
        #[serde(default)]
        expansion: f64,
    },
    /// Compressible Neo-Hookean: σ = (K/2)(J − 1/J) I + (G/J) dev(J^(-2/3) F Fᵀ).
    NeoHookean {
        /// Name bodies refer to.
        name: String,
        /// Density in the reference state (kg/m³).
        density: f64,
        /// Bulk modulus K (Pa) of the linearised response.
        bulk: f64,
        /// Shear modulus G (Pa) of the linearised response.
        shear: f64,
    },
    /// J2 (von Mises) elastic-plastic in rate form with radial return and linear
    /// isotropic hardening: yield when √(3/2 s:s) > σ_y + H ε̄ᵖ.
    J2Plastic {
        /// Name bodies refer to.
        name: String,
        /// Density (kg/m³).
        density: f64,
        /// Bulk modulus K (Pa).
        bulk: f64,
        /// Shear modulus G (Pa).
        shear: f64,
        /// Initial yield stress σ_y (Pa, tensile), > 0.
        yield_stress: f64,
        /// Hardening modulus H = dσ_y/dε̄ᵖ (Pa), ≥ 0 (0: perfectly plastic).
        #[serde(default)]
        hardening: f64,
        /// Linear thermal expansion coefficient α, ≥ 0.
        #[serde(default)]
        expansion: f64,
    },
    /// Generalized Maxwell solid: elastic bulk response; deviatoric stress
    /// s = 2G∞ e + Σ sᵢ with ṡᵢ = 2Gᵢ D′ − sᵢ/τᵢ (a spring G∞ in parallel with one
    /// spring–dashpot branch per Prony term).
    Maxwell {
        /// Name bodies refer to.
        name: String,
        /// Density (kg/m³).
        density: f64,
        /// Bulk modulus K (Pa).
        bulk: f64,
        /// Long-term (fully relaxed) shear modulus G∞ (Pa), ≥ 0.
        #[serde(default)]
        shear: f64,
        /// The Prony series: one Maxwell branch per term, at least one.
        prony: Vec<PronyTerm>,
        /// Linear thermal expansion coefficient α, ≥ 0.
        #[serde(default)]
        expansion: f64,
    },
}

/// One term Gᵢ exp(−t/τᵢ) of a relaxation modulus G(t) = G∞ + Σ Gᵢ exp(−t/τᵢ).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PronyTerm {
    /// Branch shear modulus Gᵢ (Pa), > 0.
    pub shear: f64,
    /// Relaxation time τᵢ = ηᵢ/Gᵢ (s), > 0.
    pub time: f64,
}

/// Cauchy stress in plane strain (Pa): the in-plane tensor and the out-of-plane σ_zz.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stress {
    /// σ_xx.
    pub xx: f64,
    /// σ_yy.
    pub yy: f64,
    /// σ_xy.
    pub xy: f64,
    /// σ_zz.
    pub zz: f64,
}

impl Stress {
    /// Pressure, −tr σ / 3 (positive in compression).
    pub fn pressure(&self) -> f64 {
        -(self.xx + self.yy + self.zz) / 3.0
    }

    /// tr σ = σ_xx + σ_yy + σ_zz.
    #[inline(always)]
    pub fn trace(&self) -> f64 {
        self.xx + self.yy + self.zz
    }

    /// In-plane principal stress difference σ₁ − σ₂ ≥ 0 (what photoelasticity shows).
    pub fn principal_difference(&self) -> f64 {
        let d = 0.5 * (self.xx - self.yy);
        2.0 * (d * d + self.xy * self.xy).sqrt()
    }

    /// Von Mises equivalent stress √(3/2 s:s).
    pub fn von_mises(&self) -> f64 {
        let m = self.trace() / 3.0;
        let (a, b, c) = (self.xx - m, self.yy - m, self.zz - m);
        (1.5 * (a * a + b * b + c * c + 2.0 * self.xy * self.xy)).sqrt()
    }

    /// Energy density of a linear elastic state with this stress: p²/(2K) + s:s/(4G).
    pub fn linear_energy_density(&self, bulk: f64, shear: f64) -> f64 {
        let m = (self.xx + self.yy + self.zz) / 3.0;
        let (a, b, c) = (self.xx - m, self.yy - m, self.zz - m);
        m * m / (2.0 * bulk) + (a * a + b * b + c * c + 2.0 * self.xy * self.xy) / (4.0 * shear)
    }
}

/// s:s of a deviatoric branch stress stored as (xx, yy, xy), s_zz = −(xx + yy).
#[inline(always)]
pub fn branch_norm2(s: [f64; 3]) -> f64 {
    let zz = -(s[0] + s[1]);
    s[0] * s[0] + s[1] * s[1] + zz * zz + 2.0 * s[2] * s[2]
}

fn positive(key: String, v: f64) -> Result<(), InputError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(InputError::new(key, v, "must be a finite number > 0"))
    }
}

fn non_negative(key: String, v: f64) -> Result<(), InputError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(InputError::new(key, v, "must be a finite number >= 0"))
    }
}

impl Material {
    /// The material's name.
    pub fn name(&self) -> &str {
        match self {
            Material::LinearElastic { name, .. }
            | Material::NeoHookean { name, .. }
            | Material::J2Plastic { name, .. }
            | Material::Maxwell { name, .. } => name,
        }
    }

    /// Density (kg/m³).
    pub fn density(&self) -> f64 {
        match *self {
            Material::LinearElastic { density, .. }
            | Material::NeoHookean { density, .. }
            | Material::J2Plastic { density, .. }
            | Material::Maxwell { density, .. } => density,
        }
    }

    /// (K, G) of the instantaneous (stiffest) response: for a Maxwell solid the unrelaxed
    /// shear modulus G∞ + Σ Gᵢ.
    pub fn moduli(&self) -> (f64, f64) {
        match self {
            Material::LinearElastic { bulk, shear, .. }
            | Material::NeoHookean { bulk, shear, .. }
            | Material::J2Plastic { bulk, shear, .. } => (*bulk, *shear),
            Material::Maxwell {
                bulk, shear, prony, ..
            } => (*bulk, shear + prony.iter().map(|t| t.shear).sum::<f64>()),
        }
    }

    /// Thermal expansion coefficient α (0 for models without one).
    pub fn expansion(&self) -> f64 {
        match *self {
            Material::LinearElastic { expansion, .. }
            | Material::J2Plastic { expansion, .. }
            | Material::Maxwell { expansion, .. } => expansion,
            Material::NeoHookean { .. } => 0.0,
        }
    }

    /// Maxwell branches each point of this material stores (0 for the others).
    pub fn branches(&self) -> usize {
        match self {
            Material::Maxwell { prony, .. } => prony.len(),
            _ => 0,
        }
    }

    /// Plane-strain dilatational wave speed √((K + 4G/3)/ρ) of the undeformed material,
    /// with the instantaneous moduli: what limits the stable time step.
    pub fn wave_speed(&self) -> f64 {
        let (k, g) = self.moduli();
        ((k + 4.0 * g / 3.0) / self.density()).sqrt()
    }

    /// Checks every parameter; `key` is where the material sits (e.g. `material[1]`).
    pub fn validate(&self, key: &str) -> Result<(), InputError> {
        let k = |f: &str| format!("{key}.{f}");
        positive(k("density"), self.density())?;
        match self {
            Material::LinearElastic {
                bulk,
                shear,
                expansion,
                ..
            } => {
                positive(k("bulk"), *bulk)?;
                positive(k("shear"), *shear)?;
                non_negative(k("expansion"), *expansion)?;
            }
            Material::NeoHookean { bulk, shear, .. } => {
                positive(k("bulk"), *bulk)?;
                positive(k("shear"), *shear)?;
            }
            Material::J2Plastic {
                bulk,
                shear,
                yield_stress,
                hardening,
                expansion,
                ..
            } => {
                positive(k("bulk"), *bulk)?;
                positive(k("shear"), *shear)?;
                positive(k("yield_stress"), *yield_stress)?;
                non_negative(k("hardening"), *hardening)?;
                non_negative(k("expansion"), *expansion)?;
            }
            Material::Maxwell {
                bulk,
                shear,
                prony,
                expansion,
                ..
            } => {
                positive(k("bulk"), *bulk)?;
                non_negative(k("shear"), *shear)?;
                non_negative(k("expansion"), *expansion)?;
                if prony.is_empty() {
                    return Err(InputError::new(
                        k("prony"),
                        "[]",
                        "a Maxwell solid needs at least one Prony term {shear, time}",
                    ));
                }
                for (j, t) in prony.iter().enumerate() {
                    positive(k(&format!("prony[{j}].shear")), t.shear)?;
                    positive(k(&format!("prony[{j}].time")), t.time)?;
                }
            }
        }
        Ok(())
    }

    /// The per-point update of one stress step of length `dt` during which the body's
    /// temperature goes from `thermal.start` to `thermal.end`. Everything that depends
    /// only on the material, the step and the temperature is computed here, once per body.
    pub fn prepare(&self, dt: f64, thermal: Thermal) -> Prepared {
        let dth = self.expansion() * thermal.change();
        match self {
            Material::LinearElastic { bulk, shear, .. } => Prepared::Elastic(ElasticStep {
                dt,
                bulk: *bulk,
                shear: *shear,
                dth,
            }),
            Material::NeoHookean { bulk, shear, .. } => Prepared::NeoHookean(NeoHookeanStep {
                dt,
                bulk: *bulk,
                shear: *shear,
            }),
            Material::J2Plastic {
                bulk,
                shear,
                yield_stress,
                hardening,
                ..
            } => Prepared::J2(J2Step {
                dt,
                bulk: *bulk,
                shear: *shear,
                yield_stress: *yield_stress,
                hardening: *hardening,
                dth,
            }),
            Material::Maxwell {
                bulk, shear, prony, ..
            } => Prepared::Maxwell(MaxwellStep::new(dt, *bulk, *shear, dth, prony)),
        }
    }

    /// Stored energy of a point of reference volume `vol0`, deformation `f`, stress
    /// `stress` and Maxwell branch stresses `branches` (J per unit thickness). For the
    /// rate models it is the elastic energy of the stress (thermal and plastic strains
    /// store none); a Maxwell solid adds each branch's spring energy sᵢ:sᵢ/(4Gᵢ).
    #[inline]
    pub fn stored_energy(
        &self,
        vol0: f64,
        f: DMat2,
        stress: &Stress,
        branches: &[[f64; 3]],
    ) -> f64 {
        match self {
            Material::LinearElastic { bulk, shear, .. }
            | Material::J2Plastic { bulk, shear, .. } => {
                vol0 * f.determinant() * stress.linear_energy_density(*bulk, *shear)
            }
            Material::NeoHookean { bulk, shear, .. } => {
                let j = f.determinant();
                let b = f * f.transpose();
                let c = j.cbrt();
                let tr = (b.x_axis.x + b.y_axis.y + 1.0) / (c * c);
                vol0 * (0.5 * bulk * (0.5 * (j * j - 1.0) - j.ln()) + 0.5 * shear * (tr - 3.0))
            }
            Material::Maxwell {
                bulk, shear, prony, ..
            } => {
                let m = stress.trace() / 3.0;
                // The long-term spring carries what the branches do not.
                let mut s = [stress.xx - m, stress.yy - m, stress.xy];
                let mut w = m * m / (2.0 * bulk);
                for (t, b) in prony.iter().zip(branches) {
                    w += branch_norm2(*b) / (4.0 * t.shear);
                    s = [s[0] - b[0], s[1] - b[1], s[2] - b[2]];
                }
                if *shear > 0.0 {
                    w += branch_norm2(s) / (4.0 * shear);
                }
                vol0 * f.determinant() * w
            }
        }
    }

    /// [`Material::stored_energy`] of a point without Maxwell branches.
    #[inline]
    pub fn energy(&self, vol0: f64, f: DMat2, stress: &Stress) -> f64 {
        self.stored_energy(vol0, f, stress, &[])
    }
}

/// Cauchy stress of the compressible Neo-Hookean model in plane strain (b_zz = 1).
pub fn neo_hookean_stress(f: DMat2, bulk: f64, shear: f64) -> Stress {
    let j = f.determinant();
    let b = f * f.transpose();
    // J^(-2/3) through cbrt: pow is several times slower and this runs per point.
    let c = j.cbrt();
    let scale = 1.0 / (c * c);
    let (bxx, byy, bxy, bzz) = (
        scale * b.x_axis.x,
        scale * b.y_axis.y,
        scale * b.x_axis.y,
        scale,
    );
    let mean = (bxx + byy + bzz) / 3.0;
    let p = 0.5 * bulk * (j - 1.0 / j);
    let g = shear / j;
    Stress {
        xx: p + g * (bxx - mean),
        yy: p + g * (byy - mean),
        xy: g * bxy,
        zz: p + g * (bzz - mean),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn maxwell(prony: Vec<PronyTerm>) -> Material {
        Material::Maxwell {
            name: "m".into(),
            density: 1.0,
            bulk: 1.0,
            shear: 0.1,
            prony,
            expansion: 0.0,
        }
    }

    #[test]
    fn wave_speed_uses_the_instantaneous_modulus() {
        let lin = Material::LinearElastic {
            name: "a".into(),
            density: 1.0,
            bulk: 1.0,
            shear: 0.5,
            expansion: 0.0,
        };
        assert!((lin.wave_speed() - 1.2910).abs() < 1e-4);
        let m = maxwell(vec![PronyTerm {
            shear: 0.4,
            time: 1.0,
        }]);
        assert_eq!(m.moduli(), (1.0, 0.5));
        assert!((m.wave_speed() - lin.wave_speed()).abs() < 1e-15);
    }

    #[test]
    fn bad_parameters_name_the_key() {
        let j2 = |y: f64, h: f64, a: f64| Material::J2Plastic {
            name: "j".into(),
            density: 1.0,
            bulk: 1.0,
            shear: 0.5,
            yield_stress: y,
            hardening: h,
            expansion: a,
        };
        assert!(j2(0.1, 0.0, 0.0).validate("material[0]").is_ok());
        let e = j2(-0.1, 0.0, 0.0).validate("material[0]").unwrap_err();
        assert_eq!(e.key, "material[0].yield_stress");
        assert_eq!(e.value, "-0.1");
        let e = j2(0.1, f64::NAN, 0.0).validate("material[0]").unwrap_err();
        assert_eq!(e.key, "material[0].hardening");
        let e = j2(0.1, 0.0, -1e-5).validate("material[2]").unwrap_err();
        assert_eq!(e.key, "material[2].expansion");
        let e = maxwell(vec![]).validate("material[1]").unwrap_err();
        assert_eq!(e.key, "material[1].prony");
        let e = maxwell(vec![PronyTerm {
            shear: 1.0,
            time: -2.0,
        }])
        .validate("material[1]")
        .unwrap_err();
        assert_eq!(e.key, "material[1].prony[0].time");
        assert!(e.to_string().contains("-2"), "{e}");
    }

    #[test]
    fn scenario_syntax() {
        #[derive(Deserialize)]
        struct File {
            material: Vec<Material>,
        }
        let f: File = toml::from_str(
            r#"
            [[material]]
            model = "j2_plastic"
            name = "hmx"
            density = 1900.0
            bulk = 14.2e9
            shear = 5.8e9
            yield_stress = 0.26e9
            hardening = 1e8
            [[material]]
            model = "maxwell"
            name = "binder"
            density = 1280.0
            bulk = 3e9
            shear = 0.23e6
            prony = [{ shear = 1e6, time = 1e-6 }, { shear = 1e7, time = 1e-8 }]
            expansion = 2e-4
            "#,
        )
        .unwrap();
        assert_eq!(f.material[1].branches(), 2);
        assert_eq!(f.material[1].expansion(), 2e-4);
        assert_eq!(f.material[0].expansion(), 0.0);
    }
}
