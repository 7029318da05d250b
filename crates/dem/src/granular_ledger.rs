//! The energy ledger's split under the granular law ([`crate::granular`]): what one
//! contact's step dissipated, what its springs hold before and after, and what changed
//! without work, from the history before and after [`crate::granular::respond`] and
//! its response, recomputed with the operations the response was computed with (so a
//! spring that stuck is told from one that slid by an exact comparison). The
//! derivation is in docs/architecture.md (*The energy ledger*).

use crate::granular::{self, GranularParams, Tangential, WIDTH};
use crate::law::{Contact, LedgerTerms, Prior, Response};
use crate::math::{self, AngVector, Components, Tangent, TangentOps, TAN};
use std::ops::{Add, Mul};

/// The dashpot's and the Coulomb cap's shares of one spring's step: stiffness `k`,
/// dashpot `eta`, driven at rate `u` over `dt` from `x0` (the spring carried to this
/// step, before its increment) to `x1`. A spring that stuck ends at x0 + u Δt and its
/// dashpot took η|u|² Δt; one that slid was reset so that spring and dashpot give the
/// capped force F = −k x1 − η u, whose work −F·u Δt less the spring's change
/// ½k(|x1|² − |x0|²) the cap took (dashpot included, as in the linear law's ledger).
#[inline]
fn spring<T>(k: f64, eta: f64, x0: T, x1: T, u: T, dt: f64) -> (f64, f64)
where
    T: TangentOps + Copy + PartialEq + Add<Output = T> + Mul<f64, Output = T>,
{
    let dash = u.quad(eta) * dt;
    if x1 == x0 + u * dt {
        (dash, 0.0)
    } else {
        let slip = k * (x1.dot(u) * dt - 0.5 * (x1.dot(x1) - x0.dot(x0))) + dash;
        (0.0, slip)
    }
}

/// a · b of two angular vectors (scalars in 2D).
fn ang_dot(a: AngVector, b: AngVector) -> f64 {
    (0..AngVector::N).map(|k| a.get(k) * b.get(k)).sum()
}

/// The ledger's terms of a contact that [`granular::respond`] took from `before` to
/// `after` over `dt`, answering `r`.
pub(crate) fn terms(
    p: &GranularParams,
    c: &Contact,
    before: &[f64; WIDTH],
    after: &[f64; WIDTH],
    r: &Response,
    dt: f64,
    prior: &Prior,
) -> LedgerTerms {
    let (a_prev, roll, twist) = granular::SLOTS;
    let n = c.n;
    let part = granular::normal_part(p, c);
    let a = part.a;
    let a0 = (prior.overlap.max(0.0) * c.r_eff).sqrt();
    let (kt, kt0) = (
        granular::tangential_stiffness(p, a),
        granular::tangential_stiffness(p, a0),
    );
    let fn_crit = r.normal.abs();
    let eta_t = p.x_gamma_t * part.eta_n;
    let mut t = LedgerTerms {
        normal: granular::stored_split(p, c.overlap, c.r_eff, after).normal,
        ..Default::default()
    };
    let damping_normal = (r.normal - part.fne) * c.v.dot(n) * dt;

    // Tangential: the spring as respond carries it (rescaled, then turned keeping its
    // length), and its energy at the stiffness before and after.
    let x0 = Tangent::from_slice(&before[..TAN]);
    let mut xs = x0;
    if p.tangential == Tangential::MindlinRescale && a < before[a_prev] {
        xs *= a / before[a_prev];
    }
    let xc = math::carry_keeping_length(xs, n, kt, p.mu * fn_crit);
    let x1 = Tangent::from_slice(&after[..TAN]);
    let vt = math::tangential_velocity(c.v, n, c.spin);
    let (dash, slip) = spring(kt, eta_t, xc, x1, vt, dt);
    t.damping_tangential = dash;
    t.damping = damping_normal + dash;
    t.friction = slip;
    t.tangential = x1.quad(0.5 * kt);
    t.tangential_before = x0.quad(0.5 * kt0);
    let mut softening = t.tangential_before - xc.quad(0.5 * kt);

    if let Some(rl) = p.rolling {
        let x0 = Tangent::from_slice(&before[roll..roll + TAN]);
        let xc = math::carry_keeping_length(x0, n, rl.kr, rl.mu_r * fn_crit);
        let x1 = Tangent::from_slice(&after[roll..roll + TAN]);
        let u = math::roll_velocity(c.w_rel, n) * c.r_eff;
        (t.rolling_damping, t.rolling_friction) = spring(rl.kr, rl.gamma_r, xc, x1, u, dt);
        t.rolling = x1.quad(0.5 * rl.kr);
        t.rolling_before = x0.quad(0.5 * rl.kr);
        softening += t.rolling_before - xc.quad(0.5 * rl.kr);
    }
    if p.twisting {
        // marshall: k_tw = ½ k_t a², η_tw = ½ η_t a², both at this step's a.
        let (k, k0) = (0.5 * kt * a * a, 0.5 * kt0 * a0 * a0);
        let (th0, th1) = (before[twist], after[twist]);
        let u = math::twist_rate(c.w_rel, n);
        (t.twisting_damping, t.twisting_friction) = spring(k, 0.5 * eta_t * a * a, th0, th1, u, dt);
        t.twisting = 0.5 * k * th1 * th1;
        t.twisting_before = 0.5 * k0 * th0 * th0;
        softening += t.twisting_before - 0.5 * k * th0 * th0;
    }
    t.softening = softening;
    // The tangential force turns body i about R_i − δ/2 and j about R_j − δ/2, while its
    // slip (and so the springs' and dashpots' booking) is read with R_i and R_j: the
    // bodies receive −(δ/2)(n × F_t)·(ω_i + ω_j) more power than booked.
    t.lever = 0.5 * c.overlap * ang_dot(r.moment, prior.omega_sum) * dt;
    t
}
