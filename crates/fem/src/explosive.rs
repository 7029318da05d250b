//! Explosive parameter sets: JWL for the detonation products, a shock (Us–up)
//! Mie–Grüneisen form for the unreacted solid, and the CJ figures of the programmed burn.
//!
//! Built-in sets (values as tabulated in `shared/reference/physics.md` §1):
//!
//! | name | products (JWL) | unreacted (Us = c0 + s·up, Γ0) |
//! |---|---|---|
//! | `tnt` | Dobratz 1981 LLNL handbook, the AUTODYN/LS-DYNA library set (E0 = 6 GPa) | Marsh 1980 LASL Hugoniot data (c0 = 2390 m/s, s = 2.05); Γ0 = 0.96 thermodynamic estimate |
//! | `tnt_llnl1985` | Dobratz & Crawford 1985, UCRL-52997 Chg. 2 (E0 = 7 GPa) | as `tnt` |
//! | `pe4` | C-4, Dobratz & Crawford 1985 (PE4 is the UK equivalent of C-4) | placeholder c0 = 2500 m/s, s = 2.0, Γ0 = 1.0 — order of magnitude only (unverified) |
//!
//! The paper (xue-2019, App. A) takes its sets from Price et al. 2015, which could not be
//! retrieved; any set can be given in full in the scenario instead.

use grains_core::input::{positive, shown, InputError};
use serde::{Deserialize, Serialize};

/// JWL products: p = A(1 − ω/(R1 v))e^(−R1 v) + B(1 − ω/(R2 v))e^(−R2 v) + ωE/v, with
/// v = ρ0/ρ and E = ρ0 e the energy per unit initial volume.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Jwl {
    /// A (Pa).
    pub a: f64,
    /// B (Pa).
    pub b: f64,
    /// R1 (−).
    pub r1: f64,
    /// R2 (−).
    pub r2: f64,
    /// ω, the Grüneisen coefficient of the products (−).
    pub omega: f64,
    /// Detonation energy per unit initial volume E0 (Pa = J/m³).
    pub e0: f64,
}

/// Shock Mie–Grüneisen unreacted explosive: Hugoniot Us = c0 + s·up, Γρ = Γ0ρ0.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShockMg {
    /// Bulk sound speed c0 (m/s).
    pub c0: f64,
    /// Hugoniot slope s (−).
    pub s: f64,
    /// Grüneisen coefficient Γ0 (−).
    pub gamma0: f64,
}

/// One explosive: density, CJ figures, both equations of state and where they come from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Explosive {
    /// Name shown in outputs.
    pub name: String,
    /// Initial density ρ0 (kg/m³), shared by both phases.
    pub density: f64,
    /// CJ detonation velocity D (m/s).
    pub detonation_velocity: f64,
    /// CJ pressure (Pa).
    pub cj_pressure: f64,
    /// Products.
    pub jwl: Jwl,
    /// Unreacted solid.
    pub unreacted: ShockMg,
    /// Where the numbers come from.
    #[serde(default)]
    pub source: String,
}

/// Names of the built-in sets.
pub const BUILT_IN: [&str; 3] = ["tnt", "tnt_llnl1985", "pe4"];

const TNT_UNREACTED: ShockMg = ShockMg {
    c0: 2390.0,
    s: 2.05,
    gamma0: 0.96,
};

impl Explosive {
    /// A built-in set by name (see [`BUILT_IN`]).
    pub fn built_in(name: &str) -> Option<Explosive> {
        let tnt_src = "JWL: Dobratz 1981 LLNL Explosives Handbook (AUTODYN/LS-DYNA library TNT); \
                       unreacted Hugoniot: Marsh 1980 LASL Shock Hugoniot Data via Dobratz & Crawford 1985; \
                       Γ0 = 0.96 thermodynamic estimate (physics.md §1.2)";
        Some(match name {
            "tnt" => Explosive {
                name: "tnt".into(),
                density: 1630.0,
                detonation_velocity: 6930.0,
                cj_pressure: 21.0e9,
                jwl: Jwl {
                    a: 373.77e9,
                    b: 3.747e9,
                    r1: 4.15,
                    r2: 0.90,
                    omega: 0.35,
                    e0: 6.0e9,
                },
                unreacted: TNT_UNREACTED,
                source: tnt_src.into(),
            },
            "tnt_llnl1985" => Explosive {
                name: "tnt_llnl1985".into(),
                density: 1630.0,
                detonation_velocity: 6930.0,
                cj_pressure: 21.0e9,
                jwl: Jwl {
                    a: 371.2e9,
                    b: 3.231e9,
                    r1: 4.15,
                    r2: 0.95,
                    omega: 0.30,
                    e0: 7.0e9,
                },
                unreacted: TNT_UNREACTED,
                source:
                    "JWL: Dobratz & Crawford 1985, LLNL Explosives Handbook UCRL-52997 Chg. 2; \
                         unreacted as \"tnt\""
                        .into(),
            },
            "pe4" => Explosive {
                name: "pe4".into(),
                density: 1601.0,
                detonation_velocity: 8193.0,
                cj_pressure: 28.0e9,
                jwl: Jwl {
                    a: 609.77e9,
                    b: 12.95e9,
                    r1: 4.50,
                    r2: 1.40,
                    omega: 0.25,
                    e0: 9.0e9,
                },
                unreacted: ShockMg {
                    c0: 2500.0,
                    s: 2.0,
                    gamma0: 1.0,
                },
                source:
                    "JWL: C-4, Dobratz & Crawford 1985 (PE4 = UK C-4); unreacted c0, s, Γ0 are \
                         placeholders of the right order (Price et al. 2015 not retrieved)"
                        .into(),
            },
            _ => return None,
        })
    }

    /// Chemical energy per unit mass Q = E0/ρ0 (J/kg).
    pub fn specific_energy(&self) -> f64 {
        self.jwl.e0 / self.density
    }

    /// CJ relative volume V_CJ = 1 − P_CJ/(ρ0 D²).
    pub fn v_cj(&self) -> f64 {
        1.0 - self.cj_pressure / (self.density * self.detonation_velocity.powi(2))
    }

    /// JWL pressure at the CJ point, p(V_CJ, E0 + ½P_CJ(1 − V_CJ)); equals P_CJ for a
    /// consistent set.
    pub fn jwl_cj_pressure(&self) -> f64 {
        let v = self.v_cj();
        let e = self.jwl.e0 + 0.5 * self.cj_pressure * (1.0 - v);
        crate::eos::jwl_pressure(&self.jwl, v, e)
    }

    /// Checks every parameter; `key` is the scenario path of this set.
    pub fn validate(&self, key: &str) -> Result<(), InputError> {
        let k = |f: &str| format!("{key}.{f}");
        positive(&k("density"), self.density)?;
        positive(&k("detonation_velocity"), self.detonation_velocity)?;
        positive(&k("cj_pressure"), self.cj_pressure)?;
        let j = &self.jwl;
        for (f, v) in [
            ("jwl.a", j.a),
            ("jwl.b", j.b),
            ("jwl.r1", j.r1),
            ("jwl.r2", j.r2),
            ("jwl.omega", j.omega),
            ("jwl.e0", j.e0),
        ] {
            positive(&k(f), v)?;
        }
        let u = &self.unreacted;
        for (f, v) in [
            ("unreacted.c0", u.c0),
            ("unreacted.s", u.s),
            ("unreacted.gamma0", u.gamma0),
        ] {
            positive(&k(f), v)?;
        }
        let limit = self.density * self.detonation_velocity.powi(2);
        if self.cj_pressure >= limit {
            return Err(InputError::new(
                k("cj_pressure"),
                shown(self.cj_pressure),
                format!("must be below ρ0·D² = {} Pa (else V_CJ ≤ 0)", shown(limit)),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The built-in sets reproduce P_CJ at their CJ point (eos_check.py: to 0.1 GPa).
    #[test]
    fn built_in_sets_are_consistent_at_cj() {
        for name in BUILT_IN {
            let x = Explosive::built_in(name).unwrap();
            x.validate("charge").unwrap();
            let p = x.jwl_cj_pressure();
            assert!((p - x.cj_pressure).abs() < 0.15e9, "{name}: {p}");
        }
        let tnt = Explosive::built_in("tnt").unwrap();
        assert!((tnt.v_cj() - 0.7317).abs() < 1e-4);
        assert!(Explosive::built_in("rdx").is_none());
    }

    #[test]
    fn non_positive_parameters_are_refused() {
        let mut x = Explosive::built_in("tnt").unwrap();
        x.jwl.r1 = 0.0;
        let e = x.validate("charge.custom").unwrap_err();
        assert_eq!(e.key, "charge.custom.jwl.r1");
        let mut x = Explosive::built_in("tnt").unwrap();
        x.cj_pressure = 1e12;
        assert!(x.validate("c").is_err());
    }
}
