//! Contact laws and the per-material-pair parameter table the force kernel reads.
//!
//! Two routes lead to the same kernel (linear spring-dashpot normal force, incremental
//! tangential spring with a Coulomb cap):
//!
//! * `material` (xue-2019 App. B): Kn = (Y_i + Y_j)/2, Kt = (G_i + G_j)/2, normal damping
//!   force 2ξ√(Kn m_eff)·v_n with ξ = −ln e / √(ln²e + π²), μ and e averaged over the pair.
//!   Unclamped, a binary collision returns exactly e.
//! * `hooke_history` (LAMMPS `pair gran/hooke/history kn kt γn γt μ`): damping force
//!   m_eff γn v_n normal and m_eff γt v_t tangential, the LAMMPS convention.
//!
//! `limit_damping` (LAMMPS keyword of the same name) clamps the normal force at zero so a
//! contact never pulls. The pull happens only at the end of a contact, where the dashpot
//! outweighs the spring; clamping cuts that phase short, so particles leave sooner and
//! faster: the measured restitution exceeds e, by more the lower e is.

use crate::material::Material;
use serde::{Deserialize, Serialize};

/// The contact model, as chosen in the scenario's `[contact]` table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "model", rename_all = "snake_case", deny_unknown_fields)]
pub enum ContactModel {
    /// Parameters derived from the materials (Y, ν, e, μ).
    Material {
        /// Clamp the normal force at zero (no attraction at separation).
        #[serde(default)]
        limit_damping: bool,
    },
    /// LAMMPS `gran/hooke/history` parameters, applied to every pair and wall.
    HookeHistory {
        /// Normal stiffness (N/m per unit thickness).
        kn: f64,
        /// Tangential stiffness.
        kt: f64,
        /// Normal damping rate γn (1/s); force m_eff γn v_n.
        gamma_n: f64,
        /// Tangential damping rate γt (1/s).
        gamma_t: f64,
        /// Coulomb friction coefficient.
        mu: f64,
        /// Clamp the normal force at zero.
        #[serde(default)]
        limit_damping: bool,
    },
}

impl ContactModel {
    /// LAMMPS `gran/hooke/history kn NULL gamma_n NULL mu 0` (`NULL`: LAMMPS's own
    /// k_t = 2/7 k_n and γt = γn/2), the law of the peer decks.
    pub fn hooke_history(kn: f64, gamma_n: f64, mu: f64) -> Self {
        ContactModel::HookeHistory {
            kn,
            // LAMMPS's expression, so the spring is its own to the last bit.
            kt: kn * 2.0 / 7.0,
            gamma_n,
            gamma_t: 0.5 * gamma_n,
            mu,
            limit_damping: false,
        }
    }

    /// The linear model of a set-up whose contacts a granular law carries
    /// ([`crate::setup::Setup::granular`]), which never reads it: unit springs, no
    /// damping or friction, so it passes the linear model's checks.
    pub fn unused() -> Self {
        ContactModel::HookeHistory {
            kn: 1.0,
            kt: 1.0,
            gamma_n: 0.0,
            gamma_t: 0.0,
            mu: 0.0,
            limit_damping: false,
        }
    }
}

impl Default for ContactModel {
    fn default() -> Self {
        ContactModel::Material {
            limit_damping: false,
        }
    }
}

/// Damping ratio ξ of the linear oscillator that rebounds with restitution e.
pub fn damping_ratio(e: f64) -> f64 {
    if e >= 1.0 {
        return 0.0;
    }
    let l = e.ln();
    -l / (l * l + std::f64::consts::PI.powi(2)).sqrt()
}

/// Resolved parameters of one material pair, read by the force kernel. Both routes are
/// folded into one branch-free form: dashpot c_n = `dash_sqrt`·√m_eff + `gamma_n`·m_eff
/// (the first term is the material route's 2ξ√(K_n m_eff), the second LAMMPS's m_eff γn),
/// so the kernel can run over many contacts at once without asking which route it is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairParams {
    /// Normal stiffness.
    pub kn: f64,
    /// Tangential stiffness (> 0).
    pub kt: f64,
    /// 1 / kt.
    pub inv_kt: f64,
    /// Friction coefficient.
    pub mu: f64,
    /// 2ξ√kn (material route; 0 for LAMMPS parameters).
    pub dash_sqrt: f64,
    /// Normal damping rate γn (LAMMPS route; 0 for the material route).
    pub gamma_n: f64,
    /// Tangential damping rate γt — the dashpot is m_eff γt.
    pub gamma_t: f64,
    /// Lowest normal force: 0 with `limit_damping`, −∞ without.
    pub fn_floor: f64,
}

impl Default for PairParams {
    fn default() -> Self {
        PairParams::lammps(1.0, 1.0, 0.0, 0.0, 0.0, false)
    }
}

impl PairParams {
    /// The material route: stiffnesses, friction and restitution e (ξ from e).
    pub fn material(kn: f64, kt: f64, mu: f64, e: f64, limit_damping: bool) -> Self {
        PairParams {
            kn,
            kt,
            inv_kt: 1.0 / kt,
            mu,
            dash_sqrt: 2.0 * damping_ratio(e) * kn.sqrt(),
            gamma_n: 0.0,
            gamma_t: 0.0,
            fn_floor: if limit_damping {
                0.0
            } else {
                f64::NEG_INFINITY
            },
        }
    }

    /// The LAMMPS `gran/hooke/history` route.
    pub fn lammps(
        kn: f64,
        kt: f64,
        gamma_n: f64,
        gamma_t: f64,
        mu: f64,
        limit_damping: bool,
    ) -> Self {
        PairParams {
            kn,
            kt,
            inv_kt: 1.0 / kt,
            mu,
            dash_sqrt: 0.0,
            gamma_n,
            gamma_t,
            fn_floor: if limit_damping {
                0.0
            } else {
                f64::NEG_INFINITY
            },
        }
    }

    /// Normal dashpot coefficient for a pair of effective mass `m_eff`.
    #[inline(always)]
    pub fn normal_dashpot(&self, m_eff: f64) -> f64 {
        self.dash_sqrt * m_eff.sqrt() + self.gamma_n * m_eff
    }

    /// Restitution coefficient of a normal binary collision with this pair (unclamped).
    pub fn restitution(&self, m_eff: f64) -> f64 {
        let c = self.normal_dashpot(m_eff);
        let w0 = (self.kn / m_eff).sqrt();
        let zeta = c / (2.0 * m_eff * w0);
        if zeta >= 1.0 {
            return 0.0;
        }
        (-zeta * std::f64::consts::PI / (1.0 - zeta * zeta).sqrt()).exp()
    }

    /// Duration π/ω_d of a normal binary collision (damped linear oscillator).
    pub fn contact_time(&self, m_eff: f64) -> f64 {
        let c = self.normal_dashpot(m_eff);
        let w0 = (self.kn / m_eff).sqrt();
        let zeta = c / (2.0 * m_eff * w0);
        std::f64::consts::PI / (w0 * (1.0 - zeta * zeta).max(0.0).sqrt())
    }
}

/// Parameters for every ordered pair of materials, flattened `[a * n + b]`: the linear
/// law's [`PairParams`] by default, or another law's (`crate::granular`).
#[derive(Clone, Debug, Default)]
pub struct PairTable<P = PairParams> {
    n: usize,
    table: Vec<P>,
}

impl PairTable {
    /// Builds the table. The materials must already be validated for the chosen model
    /// (see [`crate::setup`]); missing values here are treated as zero.
    pub fn new(model: &ContactModel, materials: &[Material]) -> Self {
        PairTable::from_fn(materials.len(), |a, b| {
            pair(model, &materials[a], &materials[b])
        })
    }
}

impl<P> PairTable<P> {
    /// The table of `n` materials whose entry (a, b) is `f(a, b)`.
    pub fn from_fn(n: usize, mut f: impl FnMut(usize, usize) -> P) -> Self {
        let mut table = Vec::with_capacity(n * n);
        for a in 0..n {
            for b in 0..n {
                table.push(f(a, b));
            }
        }
        PairTable { n, table }
    }

    /// Parameters of the pair (a, b).
    #[inline(always)]
    pub fn get(&self, a: usize, b: usize) -> &P {
        &self.table[a * self.n + b]
    }

    /// Number of materials.
    pub fn len(&self) -> usize {
        self.n
    }

    /// True when there are no materials.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Every entry (for time-step bounds).
    pub fn iter(&self) -> impl Iterator<Item = &P> {
        self.table.iter()
    }
}

fn pair(model: &ContactModel, a: &Material, b: &Material) -> PairParams {
    match *model {
        ContactModel::Material { limit_damping } => {
            let y = 0.5 * (a.youngs.unwrap_or(0.0) + b.youngs.unwrap_or(0.0));
            let g = 0.5 * (a.shear_modulus().unwrap_or(0.0) + b.shear_modulus().unwrap_or(0.0));
            let e = 0.5 * (a.restitution.unwrap_or(1.0) + b.restitution.unwrap_or(1.0));
            let mu = 0.5 * (a.friction.unwrap_or(0.0) + b.friction.unwrap_or(0.0));
            PairParams::material(y, g, mu, e, limit_damping)
        }
        ContactModel::HookeHistory {
            kn,
            kt,
            gamma_n,
            gamma_t,
            mu,
            limit_damping,
        } => PairParams::lammps(kn, kt, gamma_n, gamma_t, mu, limit_damping),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ratio_reproduces_restitution() {
        for e in [0.1, 0.3, 0.5, 0.7, 0.9, 1.0] {
            let p = PairParams::material(7.2e10, 3e10, 0.3, e, false);
            assert!((p.restitution(1e-3) - e).abs() < 1e-12, "e = {e}");
        }
    }
}
