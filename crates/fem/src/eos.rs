//! Equations of state in the linear-in-energy form the energy update needs:
//! at fixed density each gives p = a + b·e (e the specific internal energy, J/kg), so the
//! end-of-step pressure can be solved together with the energy it does work with.
//!
//! The burning mixture is the single-fluid closure of physics.md §1.3:
//! p = (1 − λ)·p_R(ρ, e) + λ·p_P(ρ, e + Q), with one energy e that starts at 0 in the
//! reactant and Q = E0/ρ0 the chemical energy, so the products hold the detonation
//! energy once λ = 1.

use crate::explosive::{Explosive, Jwl, ShockMg};

/// JWL pressure at relative volume v = ρ0/ρ and energy per initial volume E.
pub fn jwl_pressure(j: &Jwl, v: f64, e_vol: f64) -> f64 {
    let (e1, e2) = ((-j.r1 * v).exp(), (-j.r2 * v).exp());
    j.a * (1.0 - j.omega / (j.r1 * v)) * e1
        + j.b * (1.0 - j.omega / (j.r2 * v)) * e2
        + j.omega * e_vol / v
}

/// JWL pressure as a + b·e (e per unit mass) at relative volume v.
#[inline]
pub fn jwl_linear(j: &Jwl, rho0: f64, v: f64) -> (f64, f64) {
    let (e1, e2) = ((-j.r1 * v).exp(), (-j.r2 * v).exp());
    let a = j.a * (1.0 - j.omega / (j.r1 * v)) * e1 + j.b * (1.0 - j.omega / (j.r2 * v)) * e2;
    (a, j.omega * rho0 / v)
}

/// Squared isentropic sound speed of the products at v and pressure p (OpenRadioss
/// `m5law` form); `e` per unit mass.
#[inline]
pub fn jwl_sound2(j: &Jwl, rho0: f64, v: f64, e: f64, p: f64) -> f64 {
    let (e1, e2) = ((-j.r1 * v).exp(), (-j.r2 * v).exp());
    let w = j.omega;
    let bracket = j.a * e1 * (j.r1 * v - w - w / (j.r1 * v))
        + j.b * e2 * (j.r2 * v - w - w / (j.r2 * v))
        + w * rho0 * e / v
        + w * p;
    v / rho0 * bracket
}

/// Largest compression η = 1 − v used on the Hugoniot, as a fraction of its pole 1/s:
/// beyond it p_H diverges, and no state of a detonating charge gets there (the von
/// Neumann spike of TNT is at η ≈ 0.32, the pole at 0.49).
const ETA_CAP: f64 = 0.95;

/// Unreacted Mie–Grüneisen pressure as a + b·e at v (linear Us–up Hugoniot reference
/// in compression; p = ρ0c0²η + Γ0ρ0e in tension).
#[inline]
pub fn shock_linear(m: &ShockMg, rho0: f64, v: f64) -> (f64, f64) {
    let g = m.gamma0 * rho0;
    let eta = 1.0 - v;
    if eta <= 0.0 {
        return (rho0 * m.c0 * m.c0 * eta, g);
    }
    let eta = eta.min(ETA_CAP / m.s);
    let den = 1.0 - m.s * eta;
    let ph = rho0 * m.c0 * m.c0 * eta / (den * den);
    let eh = ph * eta / (2.0 * rho0);
    (ph - g * eh, g)
}

/// Squared sound speed of the unreacted solid at v, energy e and pressure p.
#[inline]
pub fn shock_sound2(m: &ShockMg, rho0: f64, v: f64, p: f64) -> f64 {
    let g = m.gamma0 * rho0;
    let rho = rho0 / v;
    let eta = 1.0 - v;
    // ∂p/∂ρ at constant e = (dη/dρ)(p_H' − Γ0ρ0 e_H'), dη/dρ = v²/ρ0.
    let dp_drho = if eta <= 0.0 {
        v * v * m.c0 * m.c0
    } else {
        let eta = eta.min(ETA_CAP / m.s);
        let den = 1.0 - m.s * eta;
        let k = rho0 * m.c0 * m.c0;
        let ph = k * eta / (den * den);
        let dph = k * (1.0 + m.s * eta) / (den * den * den);
        let deh = (ph + eta * dph) / (2.0 * rho0);
        v * v / rho0 * (dph - g * deh)
    };
    dp_drho + p * g / (rho * rho)
}

/// The mixture's EOS frozen at one burn fraction and relative volume: p = a + b·e, with
/// the JWL exponentials kept for the sound speed (the element pass needs both, and the
/// exponentials are most of the cost).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mixture {
    /// Pressure at e = 0 (Pa).
    pub a: f64,
    /// ∂p/∂e at fixed density (kg/m³).
    pub b: f64,
    lambda: f64,
    v: f64,
    exps: (f64, f64),
}

/// The mixture at burn fraction λ and relative volume v. A phase with no mass share is
/// skipped, so unburnt and fully burnt elements evaluate one EOS only.
#[inline]
pub fn mixture(x: &Explosive, lambda: f64, v: f64) -> Mixture {
    let rho0 = x.density;
    let (mut a, mut b) = (0.0, 0.0);
    let mut exps = (0.0, 0.0);
    if lambda < 1.0 {
        let (ar, br) = shock_linear(&x.unreacted, rho0, v);
        a += (1.0 - lambda) * ar;
        b += (1.0 - lambda) * br;
    }
    if lambda > 0.0 {
        let j = &x.jwl;
        exps = ((-j.r1 * v).exp(), (-j.r2 * v).exp());
        let ap = j.a * (1.0 - j.omega / (j.r1 * v)) * exps.0
            + j.b * (1.0 - j.omega / (j.r2 * v)) * exps.1;
        let bp = j.omega * rho0 / v;
        a += lambda * (ap + bp * x.specific_energy());
        b += lambda * bp;
    }
    Mixture {
        a,
        b,
        lambda,
        v,
        exps,
    }
}

impl Mixture {
    /// Squared sound speed at energy e and pressure p: the mass-fraction average of both
    /// phases' c² (each at the mixture pressure), floored at a tiny positive value.
    #[inline]
    pub fn sound2(&self, x: &Explosive, e: f64, p: f64) -> f64 {
        let (rho0, l, v) = (x.density, self.lambda, self.v);
        let mut c2 = 0.0;
        if l < 1.0 {
            c2 += (1.0 - l) * shock_sound2(&x.unreacted, rho0, v, p);
        }
        if l > 0.0 {
            let j = &x.jwl;
            let w = j.omega;
            let ep = e + x.specific_energy();
            let bracket = j.a * self.exps.0 * (j.r1 * v - w - w / (j.r1 * v))
                + j.b * self.exps.1 * (j.r2 * v - w - w / (j.r2 * v))
                + w * rho0 * ep / v
                + w * p;
            c2 += l * v / rho0 * bracket;
        }
        c2.max(1e-6 * x.unreacted.c0 * x.unreacted.c0)
    }
}

/// The mixture at burn fraction λ and relative volume v as p = a + b·e.
pub fn mixture_linear(x: &Explosive, lambda: f64, v: f64) -> (f64, f64) {
    let m = mixture(x, lambda, v);
    (m.a, m.b)
}

/// Squared sound speed of the mixture at λ, v, e and p.
pub fn mixture_sound2(x: &Explosive, lambda: f64, v: f64, e: f64, p: f64) -> f64 {
    mixture(x, lambda, v).sound2(x, e, p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::explosive::Explosive;

    fn tnt() -> Explosive {
        Explosive::built_in("tnt").unwrap()
    }

    #[test]
    fn linear_form_matches_jwl() {
        let x = tnt();
        for v in [0.7, 1.0, 2.5, 8.0] {
            let e = 3.0e6;
            let (a, b) = jwl_linear(&x.jwl, x.density, v);
            let direct = jwl_pressure(&x.jwl, v, x.density * e);
            assert!((a + b * e - direct).abs() < 1e-6 * direct.abs());
        }
    }

    /// c² from the formula equals −v²/ρ0 · dp/dv along the isentrope (dE = −p dv).
    #[test]
    fn jwl_sound_speed_is_isentropic_derivative() {
        let x = tnt();
        let (v, e) = (0.9, 4.0e6);
        let ev = x.density * e;
        let p = jwl_pressure(&x.jwl, v, ev);
        let h = 1e-6;
        let p2 = jwl_pressure(&x.jwl, v + h, ev - p * h);
        let p1 = jwl_pressure(&x.jwl, v - h, ev + p * h);
        let dpdv = (p2 - p1) / (2.0 * h);
        let c2 = -v * v / x.density * dpdv;
        let formula = jwl_sound2(&x.jwl, x.density, v, e, p);
        assert!((c2 - formula).abs() < 1e-5 * formula, "{c2} vs {formula}");
    }

    /// The same for the unreacted Mie–Grüneisen form (de = p dv/ρ0 ... per mass: de = −p d(1/ρ)).
    #[test]
    fn shock_sound_speed_is_isentropic_derivative() {
        let x = tnt();
        let m = &x.unreacted;
        let rho0 = x.density;
        for (v, e) in [(0.8, 2.0e5), (1.02, 1.0e3)] {
            let pr = |v: f64, e: f64| {
                let (a, b) = shock_linear(m, rho0, v);
                a + b * e
            };
            let p = pr(v, e);
            let h = 1e-7;
            // Along the isentrope de = −p d(1/ρ) = −p dv/ρ0.
            let dpdv = (pr(v + h, e - p * h / rho0) - pr(v - h, e + p * h / rho0)) / (2.0 * h);
            let c2 = -v * v / rho0 * dpdv;
            let formula = shock_sound2(m, rho0, v, p);
            assert!(
                (c2 - formula).abs() < 1e-4 * formula,
                "v {v}: {c2} vs {formula}"
            );
        }
        // At rest the sound speed is c0.
        let c = shock_sound2(m, rho0, 1.0, 0.0).sqrt();
        assert!((c - m.c0).abs() < 1e-9 * m.c0);
    }

    /// Fully burnt at the initial density with e = 0: the constant-volume explosion state
    /// p_JWL(1, E0).
    /// The mixture's sound speed is the mass-fraction average of the phases'.
    #[test]
    fn mixture_sound_speed_averages_the_phases() {
        let x = tnt();
        let (v, e, l) = (0.85, 2.0e5, 0.4);
        let (a, b) = mixture_linear(&x, l, v);
        let p = a + b * e;
        let direct = (1.0 - l) * shock_sound2(&x.unreacted, x.density, v, p)
            + l * jwl_sound2(&x.jwl, x.density, v, e + x.specific_energy(), p);
        assert!((mixture_sound2(&x, l, v, e, p) - direct).abs() < 1e-9 * direct);
    }

    #[test]
    fn burnt_mixture_holds_the_detonation_energy() {
        let x = tnt();
        let (a, _) = mixture_linear(&x, 1.0, 1.0);
        let direct = jwl_pressure(&x.jwl, 1.0, x.jwl.e0);
        assert!((a - direct).abs() < 1e-9 * direct);
        let (a0, b0) = mixture_linear(&x, 0.0, 1.0);
        assert_eq!(a0, 0.0);
        assert!(b0 > 0.0);
    }
}
