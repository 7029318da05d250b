//! The contact law of LAMMPS `pair_style granular` (version 29 Sep 2021): a normal force
//! (`hooke` or `hertz/material`) with one of four dampings (`velocity`, `mass_velocity`,
//! `viscoelastic`, `tsuji`), a tangential spring with history (`linear_history`,
//! `mindlin`, `mindlin_rescale`) capped by Coulomb friction, rolling resistance (`sds`)
//! and twisting resistance (`marshall`, 3D).
//!
//! [`respond`] evaluates one contact in the order LAMMPS does, so that a pair run with
//! the same parameters follows LAMMPS to round-off (`crates/dem3d/tests/lammps.rs` checks
//! forces, torques and history against LAMMPS tables; `crates/dem/tests/lammps.rs` in
//! 2D). Conventions: n is the unit normal from body i towards body j (LAMMPS's points
//! from j to i); the tangential and rolling springs are [`Tangent`]s (vectors in 3D, the
//! component along t = (−n_y, n_x) in 2D); the caps use |F_n|, damping included, as
//! LAMMPS does. Where LAMMPS mixes two materials, this module follows LAMMPS's documented
//! rule ([`GranularParams::mixed`]) rather than that version's code, which leaves the
//! models of an unlike pair unset.

use crate::math::{self, AngVector, Components, Tangent, TangentOps, TAN};
use serde::{Deserialize, Serialize};

/// Normal force model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Normal {
    /// F = k_n δ.
    Hooke,
    /// F = (4/3) E* a δ, a = √(δ R_eff).
    HertzMaterial,
}

/// Normal damping model: the dashpot η_n = `damp` × this factor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Damping {
    /// η_n = η₀.
    Velocity,
    /// η_n = η₀ m*.
    MassVelocity,
    /// η_n = η₀ a m*.
    Viscoelastic,
    /// η_n = α(e) √(m* k_n) (Hertz: k_n = (4/3)E* a), α Tsuji's fit.
    Tsuji,
    /// Tsuji's form with α solved so that a collision rebounds at e exactly
    /// ([`crate::restitution`]); not a LAMMPS model.
    Restitution,
}

/// Tangential model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Tangential {
    /// A spring of constant stiffness k_t.
    LinearHistory,
    /// Mindlin: stiffness k_t a (k_t = 8G* by default).
    Mindlin,
    /// Mindlin, with the spring scaled down by a/a_prev while the contact unloads.
    MindlinRescale,
}

/// Rolling resistance `sds`: a spring k_r and dashpot γ_r on the rolling displacement,
/// capped at μ_r |F_n|.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rolling {
    /// Rolling stiffness k_r (N/m).
    pub kr: f64,
    /// Rolling damping γ_r (N s/m).
    pub gamma_r: f64,
    /// Rolling friction coefficient μ_r.
    pub mu_r: f64,
}

/// Everything one pair's law needs, resolved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GranularParams {
    /// Normal model.
    pub normal: Normal,
    /// k_n (Hooke, N/m) or (4/3)E* (Hertz, Pa).
    pub kn: f64,
    /// Damping model.
    pub damping: Damping,
    /// η₀, or Tsuji's α(e), or the α solved for e ([`Damping::Restitution`]).
    pub damp: f64,
    /// Tangential model.
    pub tangential: Tangential,
    /// k_t (linear: N/m; Mindlin: the factor of a, Pa).
    pub kt: f64,
    /// Tangential damping as a fraction of the normal one (η_t = x_γt η_n).
    pub x_gamma_t: f64,
    /// Coulomb friction coefficient.
    pub mu: f64,
    /// Rolling resistance, if any.
    pub rolling: Option<Rolling>,
    /// Twisting resistance `marshall` (k_tw = ½ k_t a², η_tw = ½ η_t a², μ_tw = ⅔ a μ).
    pub twisting: bool,
    /// Clamp the normal force at zero (the caps then vanish with it).
    pub limit_damping: bool,
}

impl crate::contact::PairTable<GranularParams> {
    /// The widest history any pair of the table writes ([`GranularParams::history_width`]).
    pub fn history_width(&self) -> usize {
        self.iter()
            .map(GranularParams::history_width)
            .max()
            .unwrap_or(TAN)
    }
}

/// Tsuji's α(e), the fit LAMMPS uses (P:990).
pub fn tsuji_alpha(e: f64) -> f64 {
    let p = |n: i32| e.powi(n);
    1.2728 - 4.2783 * e + 11.087 * (e * e) - 22.348 * (e * e * e) + 27.467 * p(4) - 18.022 * p(5)
        + 4.8218 * p(6)
}

/// E* of two materials, 1 / ((1 − ν_i²)/E_i + (1 − ν_j²)/E_j).
pub fn effective_youngs(e: [f64; 2], nu: [f64; 2]) -> f64 {
    1.0 / ((1.0 - nu[0] * nu[0]) / e[0] + (1.0 - nu[1] * nu[1]) / e[1])
}

/// G* of two materials, 1 / (2(2 − ν_i)(1 + ν_i)/E_i + 2(2 − ν_j)(1 + ν_j)/E_j).
pub fn effective_shear(e: [f64; 2], nu: [f64; 2]) -> f64 {
    1.0 / ((2.0 * (2.0 - nu[0]) * (1.0 + nu[0]) / e[0])
        + (2.0 * (2.0 - nu[1]) * (1.0 + nu[1]) / e[1]))
}

impl GranularParams {
    /// The parameters one LAMMPS `pair_coeff` line gives (one E and ν for the pair, as
    /// LAMMPS stores them): `hertz/material E e_or_η ν` or `hooke k_n η`, the tangential
    /// k_t (`None`: 8G*, for Mindlin), x_γt and μ.
    #[allow(clippy::too_many_arguments)]
    pub fn lammps(
        normal: Normal,
        stiffness: f64,
        damping: Damping,
        damp_in: f64,
        poisson: f64,
        tangential: Tangential,
        kt: Option<f64>,
        x_gamma_t: f64,
        mu: f64,
    ) -> Self {
        let (e, nu) = ([stiffness; 2], [poisson; 2]);
        let kn = match normal {
            Normal::Hooke => stiffness,
            Normal::HertzMaterial => 4.0 / 3.0 * effective_youngs(e, nu),
        };
        GranularParams {
            normal,
            kn,
            damping,
            damp: match damping {
                Damping::Tsuji => tsuji_alpha(damp_in),
                Damping::Restitution => crate::restitution::alpha(normal, damp_in),
                _ => damp_in,
            },
            tangential,
            kt: kt.unwrap_or_else(|| 8.0 * effective_shear(e, nu)),
            x_gamma_t,
            mu,
            rolling: None,
            twisting: false,
            limit_damping: false,
        }
    }

    /// How many leading numbers of a history this law writes (the rest stay zero): the
    /// tangential spring, then the contact radius (`mindlin_rescale`), the rolling
    /// spring and the twisting angle, as far as the last one the law has.
    pub fn history_width(&self) -> usize {
        if self.twisting {
            WIDTH
        } else if self.rolling.is_some() {
            ROLL + TAN
        } else if self.tangential == Tangential::MindlinRescale {
            A_PREV + 1
        } else {
            TAN
        }
    }

    /// The parameters of an unlike pair by LAMMPS's documented mixing: E* from both
    /// materials' E and ν (`e`, `nu`), every other coefficient the geometric mean of the
    /// two like pairs' (`a`, `b`, resolved with [`GranularParams::lammps`]).
    pub fn mixed(a: &Self, b: &Self, e: [f64; 2], nu: [f64; 2]) -> Self {
        let g = |x: f64, y: f64| (x * y).sqrt();
        GranularParams {
            kn: match a.normal {
                Normal::Hooke => g(a.kn, b.kn),
                Normal::HertzMaterial => 4.0 / 3.0 * effective_youngs(e, nu),
            },
            damp: g(a.damp, b.damp),
            kt: g(a.kt, b.kt),
            x_gamma_t: g(a.x_gamma_t, b.x_gamma_t),
            mu: g(a.mu, b.mu),
            rolling: a.rolling.zip(b.rolling).map(|(p, q)| Rolling {
                kr: g(p.kr, q.kr),
                gamma_r: g(p.gamma_r, q.gamma_r),
                mu_r: g(p.mu_r, q.mu_r),
            }),
            ..*a
        }
    }
}

/// Numbers of history per contact: the tangential spring, the contact radius at the last
/// step (`mindlin_rescale`), the rolling spring and the twisting angle.
pub const WIDTH: usize = 2 * TAN + 2;
const A_PREV: usize = TAN;
const ROLL: usize = TAN + 1;
const TWIST: usize = 2 * TAN + 1;

pub use crate::law::{Contact, Response};

/// The normal force's parts at a contact: what the response and the ledger both read.
pub(crate) struct NormalPart {
    /// The contact radius a = √(δ R_eff).
    pub a: f64,
    /// The elastic normal force.
    pub fne: f64,
    /// The normal dashpot η_n.
    pub eta_n: f64,
}

/// The contact radius, elastic normal force and normal dashpot of a contact.
#[inline(always)]
pub(crate) fn normal_part(p: &GranularParams, c: &Contact) -> NormalPart {
    let a = (c.overlap * c.r_eff).sqrt();
    let (fne, knfac) = match p.normal {
        Normal::Hooke => (p.kn * c.overlap, p.kn),
        Normal::HertzMaterial => (p.kn * c.overlap * a, p.kn * a),
    };
    let damp_normal = match p.damping {
        Damping::Velocity => 1.0,
        Damping::MassVelocity => c.m_eff,
        Damping::Viscoelastic => a * c.m_eff,
        Damping::Tsuji | Damping::Restitution => (c.m_eff * knfac).sqrt(),
    };
    NormalPart {
        a,
        fne,
        eta_n: p.damp * damp_normal,
    }
}

/// The tangential stiffness at contact radius `a`: k_t, or Mindlin's k_t a.
#[inline(always)]
pub(crate) fn tangential_stiffness(p: &GranularParams, a: f64) -> f64 {
    match p.tangential {
        Tangential::LinearHistory => p.kt,
        Tangential::Mindlin | Tangential::MindlinRescale => p.kt * a,
    }
}

/// History slots: the contact radius at the last step, the rolling spring, the twist.
pub(crate) const SLOTS: (usize, usize, usize) = (A_PREV, ROLL, TWIST);

/// Evaluates one contact and advances its history `h` by `dt` (when `update`; LAMMPS's
/// set-up evaluation does not).
pub fn respond(
    p: &GranularParams,
    c: &Contact,
    h: &mut [f64; WIDTH],
    dt: f64,
    update: bool,
) -> Response {
    let n = c.n;
    let vnn = -c.v.dot(n); // LAMMPS's v_r · n_ji: < 0 while approaching
    let NormalPart { a, fne, eta_n } = normal_part(p, c);
    let mut fn_total = fne - eta_n * vnn;
    if p.limit_damping && fn_total < 0.0 {
        fn_total = 0.0;
    }
    let fn_crit = fn_total.abs();

    // Tangential.
    let vtr = math::tangential_velocity(c.v, n, c.spin);
    let f_scrit = p.mu * fn_crit;
    let mut kt = p.kt;
    let eta_t = p.x_gamma_t * eta_n;
    let mut xi = Tangent::from_slice(&h[..TAN]);
    if matches!(
        p.tangential,
        Tangential::Mindlin | Tangential::MindlinRescale
    ) {
        kt *= a;
        if p.tangential == Tangential::MindlinRescale && a < h[A_PREV] {
            xi *= a / h[A_PREV];
        }
    }
    if update {
        xi = math::carry_keeping_length(xi, n, kt, f_scrit) + vtr * dt;
        if p.tangential == Tangential::MindlinRescale {
            h[A_PREV] = a;
        }
    }
    let mut ft = -(xi * kt) - vtr * eta_t;
    let fs = ft.norm();
    if fs > f_scrit {
        if xi.norm() != 0.0 {
            xi = -(ft * (f_scrit / fs) + vtr * eta_t) * (1.0 / kt);
            ft *= f_scrit / fs;
        } else {
            ft = Tangent::default();
        }
    }
    write(h, 0, xi);

    // Rolling and twisting.
    let mut couple = AngVector::default();
    if let Some(r) = p.rolling {
        let vrl = math::roll_velocity(c.w_rel, n) * c.r_eff;
        let f_rcrit = r.mu_r * fn_crit;
        let mut xr = Tangent::from_slice(&h[ROLL..ROLL + TAN]);
        if update {
            xr = math::carry_keeping_length(xr, n, r.kr, f_rcrit) + vrl * dt;
        }
        let mut fr = -(xr * r.kr) - vrl * r.gamma_r;
        let frm = fr.norm();
        if frm > f_rcrit {
            if xr.norm() != 0.0 {
                xr = -(fr * (f_rcrit / frm) + vrl * r.gamma_r) * (1.0 / r.kr);
                fr *= f_rcrit / frm;
            } else {
                fr = Tangent::default();
            }
        }
        write(h, ROLL, xr);
        couple -= math::moment(fr, n) * c.r_eff;
    }
    if p.twisting {
        let rate = math::twist_rate(c.w_rel, n);
        let k_tw = 0.5 * kt * a * a;
        let eta_tw = 0.5 * eta_t * a * a;
        let mu_tw = 2.0 / 3.0 * a * p.mu;
        if update {
            h[TWIST] += rate * dt;
        }
        let mut m = -k_tw * h[TWIST] - eta_tw * rate;
        let sign = if rate > 0.0 {
            1.0
        } else if rate < 0.0 {
            -1.0
        } else {
            0.0
        };
        let m_crit = mu_tw * fn_crit;
        if m.abs() > m_crit {
            h[TWIST] = 1.0 / k_tw * (m_crit * sign - eta_tw * rate);
            m = -m_crit * sign;
        }
        couple += math::twist_couple(m, n);
    }
    Response {
        force: -fn_total * n + math::tangent_vector(ft, n),
        moment: math::moment(ft, n),
        couple,
        normal: fn_total,
    }
}

/// The elastic energy a contact stores at overlap δ with history `h`: the normal
/// spring's (½ k_n δ², or (2/5)(4/3)E* √R δ^{5/2} for Hertz), and ½ k |ξ|² of the
/// tangential, rolling and twisting springs at the present stiffnesses.
pub fn stored_energy(p: &GranularParams, overlap: f64, r_eff: f64, h: &[f64; WIDTH]) -> f64 {
    let s = stored_split(p, overlap, r_eff, h);
    s.normal + s.tangential + s.rolling + s.twisting
}

/// [`stored_energy`] spring by spring, in the stored fields of a
/// [`crate::law::LedgerTerms`].
pub fn stored_split(
    p: &GranularParams,
    overlap: f64,
    r_eff: f64,
    h: &[f64; WIDTH],
) -> crate::law::LedgerTerms {
    let a = (overlap * r_eff).sqrt();
    let kt = tangential_stiffness(p, a);
    let mut s = crate::law::LedgerTerms {
        normal: match p.normal {
            Normal::Hooke => 0.5 * p.kn * overlap * overlap,
            Normal::HertzMaterial => 0.4 * p.kn * a * overlap * overlap,
        },
        tangential: Tangent::from_slice(&h[..TAN]).quad(0.5 * kt),
        ..Default::default()
    };
    if let Some(r) = p.rolling {
        s.rolling = Tangent::from_slice(&h[ROLL..ROLL + TAN]).quad(0.5 * r.kr);
    }
    if p.twisting {
        s.twisting = 0.5 * (0.5 * kt * a * a) * h[TWIST] * h[TWIST];
    }
    s
}

fn write<T: Components>(h: &mut [f64], at: usize, v: T) {
    for k in 0..T::N {
        h[at + k] = v.get(k);
    }
}

/// A contact's history as seen from the pair's other particle (the two swap roles at a
/// rebuild): the tangential spring as [`math::swapped`], the rolling spring as
/// [`math::roll_swapped`], the contact radius and twisting angle the same.
pub fn swapped(h: &[f64; WIDTH]) -> [f64; WIDTH] {
    let mut out = *h;
    write(&mut out, 0, math::swapped(Tangent::from_slice(&h[..TAN])));
    write(
        &mut out,
        ROLL,
        math::roll_swapped(Tangent::from_slice(&h[ROLL..ROLL + TAN])),
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tsuji_alpha_is_lammps_fit() {
        // α(0.5) and α(0.7) as the LAMMPS reference transcription gives them.
        assert!((tsuji_alpha(0.5) - 0.340_740_625).abs() < 1e-12);
        assert!((tsuji_alpha(1.0) - 3.0e-4).abs() < 1e-12);
    }

    #[test]
    fn like_materials_mix_to_themselves() {
        let p = GranularParams::lammps(
            Normal::HertzMaterial,
            1e7,
            Damping::Tsuji,
            0.5,
            0.3,
            Tangential::Mindlin,
            None,
            1.0,
            0.1,
        );
        let m = GranularParams::mixed(&p, &p, [1e7; 2], [0.3; 2]);
        assert!((m.kn - p.kn).abs() < 1e-9 * p.kn && (m.kt - p.kt).abs() < 1e-9 * p.kt);
        // E* = E / (2(1 − ν²)), G* = E / (4(2 − ν)(1 + ν)).
        assert!((p.kn - 4.0 / 3.0 * 1e7 / (2.0 * 0.91)).abs() < 1e-6);
        assert!((p.kt - 8.0 * 1e7 / (4.0 * 1.7 * 1.3)).abs() < 1e-6);
    }
}
