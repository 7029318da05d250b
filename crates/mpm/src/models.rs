//! One stress update per point, per model. A body's [`Material`] is turned once per
//! stress pass into a [`Prepared`] step (moduli, the step length, the temperature change,
//! each Prony term's decay factor), and the kernels are compiled once per model type
//! ([`Model`]), so the hot loop never matches on the material.
//!
//! The rate models share the objective frame: the deformation gradient advances by the
//! Cayley increment and the stress (and every Maxwell branch stress) is rotated by the
//! Hughes–Winget increment of the spin before the strain increment is added. The thermal
//! strain α ΔT is isotropic in three dimensions; in plane strain the confined z direction
//! then carries σ_zz.
//!
//! Energy: the plastic work and the viscous dissipation of each point are added to its
//! `dissipated` field and the work of the thermal strain, −tr σ · α ΔT · V, to its
//! `thermal_work`, so kinetic + stored + dissipated − thermal work stays constant.

use crate::material::{branch_norm2, neo_hookean_stress, Material, PronyTerm, Stress};
use crate::thermal::Thermal;
use glam::DMat2;

/// The fields a stress update reads and writes, for a contiguous run of points (a strip).
/// Maxwell branch stresses are stored `width` per point, (xx, yy, xy) each.
pub struct MaterialView<'a> {
    /// Reference volumes.
    pub vol0: &'a [f64],
    /// Deformation gradients.
    pub def: &'a mut [DMat2],
    /// Cauchy stresses.
    pub stress: &'a mut [Stress],
    /// Equivalent plastic strain ε̄ᵖ.
    pub plastic: &'a mut [f64],
    /// Energy dissipated so far (J per unit thickness).
    pub dissipated: &'a mut [f64],
    /// Work done on the point by its thermal strain so far (J per unit thickness).
    pub thermal_work: &'a mut [f64],
    /// Maxwell branch stresses, `width` per point.
    pub branches: &'a mut [[f64; 3]],
    /// Branches stored per point.
    pub width: usize,
}

/// A material prepared for one stress step: updates point `i` of a view under the
/// velocity gradient `l` (column j holds ∂v/∂x_j).
pub trait Model: Sync {
    /// One point's update.
    fn update(&self, l: DMat2, v: &mut MaterialView, i: usize);
}

/// A body's material for one stress step; see [`Material::prepare`].
#[derive(Clone, Debug, PartialEq)]
pub enum Prepared {
    /// Hypo-elastic.
    Elastic(ElasticStep),
    /// Neo-Hookean.
    NeoHookean(NeoHookeanStep),
    /// J2 elastic-plastic.
    J2(J2Step),
    /// Generalized Maxwell.
    Maxwell(MaxwellStep),
}

/// Runs `$body` with `$m` bound to the concrete model of a [`Prepared`], so a generic
/// kernel is instantiated once per model and chosen once per call.
macro_rules! with_model {
    ($p:expr, $m:ident => $body:expr) => {
        match $p {
            $crate::models::Prepared::Elastic($m) => $body,
            $crate::models::Prepared::NeoHookean($m) => $body,
            $crate::models::Prepared::J2($m) => $body,
            $crate::models::Prepared::Maxwell($m) => $body,
        }
    };
}
pub(crate) use with_model;

/// Advances F by the Cayley (midpoint) increment: second order, and exactly orthogonal
/// under pure spin, so a rolling body's volume does not drift.
#[inline(always)]
fn advance(l: DMat2, dt: f64, f: &mut DMat2) {
    let half = 0.5 * dt * l;
    *f = (DMat2::IDENTITY - half).inverse() * (DMat2::IDENTITY + half) * *f;
}

/// The Hughes–Winget increment (I − ½ΔtW)⁻¹(I + ½ΔtW) of the spin
/// ω = W_xy = ½(∂vx/∂y − ∂vy/∂x): an exact rotation [[c, s], [−s, c]], returned as (c, s).
#[inline(always)]
fn spin(l: DMat2, dt: f64) -> (f64, f64) {
    let a = 0.5 * dt * 0.5 * (l.y_axis.x - l.x_axis.y);
    let inv = 1.0 / (1.0 + a * a);
    ((1.0 - a * a) * inv, 2.0 * a * inv)
}

/// Q t Qᵀ of the symmetric in-plane tensor (xx, yy, xy), Q = [[c, s], [−s, c]].
#[inline(always)]
fn rotate(t: [f64; 3], (c, s): (f64, f64)) -> [f64; 3] {
    let [xx, yy, xy] = t;
    [
        c * c * xx + 2.0 * c * s * xy + s * s * yy,
        s * s * xx - 2.0 * c * s * xy + c * c * yy,
        (c * c - s * s) * xy + c * s * (yy - xx),
    ]
}

/// Adds the thermal strain's work −½(tr σₙ + tr σₙ₊₁) α ΔT V (midpoint rule).
#[inline(always)]
fn thermal_work(v: &mut MaterialView, i: usize, tr_old: f64, dth: f64) {
    let vol = v.vol0[i] * v.def[i].determinant();
    v.thermal_work[i] -= 0.5 * (tr_old + v.stress[i].trace()) * dth * vol;
}

/// Hypo-elastic step: σ̇ = λ tr(D) I + 2G D − 3Kα Ṫ I in the rotated frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ElasticStep {
    /// Step (s).
    pub dt: f64,
    /// K.
    pub bulk: f64,
    /// G.
    pub shear: f64,
    /// Thermal strain increment α ΔT.
    pub dth: f64,
}

/// The elastic update of the rate models: F advances, the stress rotates with the spin
/// and takes λ tr(D) I + 2G D − 3Kα ΔT I. Returns the new stress; the old one is `st`.
#[inline(always)]
fn elastic(
    l: DMat2,
    dt: f64,
    bulk: f64,
    shear: f64,
    dth: f64,
    f: &mut DMat2,
    st: &Stress,
) -> Stress {
    advance(l, dt, f);
    let (dxx, dyy) = (l.x_axis.x, l.y_axis.y);
    let dxy = 0.5 * (l.y_axis.x + l.x_axis.y);
    let [rxx, ryy, rxy] = rotate([st.xx, st.yy, st.xy], spin(l, dt));
    let lambda = bulk - 2.0 * shear / 3.0;
    let mut vol = lambda * (dxx + dyy) * dt;
    // A branch, not a subtracted zero: the isothermal path is the common one.
    if dth != 0.0 {
        vol -= 3.0 * bulk * dth;
    }
    Stress {
        xx: rxx + vol + 2.0 * shear * dxx * dt,
        yy: ryy + vol + 2.0 * shear * dyy * dt,
        xy: rxy + 2.0 * shear * dxy * dt,
        zz: st.zz + vol,
    }
}

impl Model for ElasticStep {
    #[inline(always)]
    fn update(&self, l: DMat2, v: &mut MaterialView, i: usize) {
        let old = v.stress[i];
        v.stress[i] = elastic(
            l,
            self.dt,
            self.bulk,
            self.shear,
            self.dth,
            &mut v.def[i],
            &old,
        );
        if self.dth != 0.0 {
            thermal_work(v, i, old.trace(), self.dth);
        }
    }
}

/// Neo-Hookean step: F advances, σ follows from F.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NeoHookeanStep {
    /// Step (s).
    pub dt: f64,
    /// K.
    pub bulk: f64,
    /// G.
    pub shear: f64,
}

impl Model for NeoHookeanStep {
    #[inline(always)]
    fn update(&self, l: DMat2, v: &mut MaterialView, i: usize) {
        advance(l, self.dt, &mut v.def[i]);
        v.stress[i] = neo_hookean_stress(v.def[i], self.bulk, self.shear);
    }
}

/// J2 step: elastic predictor in the rotated frame, radial return onto
/// q = σ_y + H ε̄ᵖ (q = √(3/2 s:s)), which is exact for linear hardening:
/// Δγ = (q_trial − σ_y − H ε̄ᵖ)/(3G + H).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct J2Step {
    /// Step (s).
    pub dt: f64,
    /// K.
    pub bulk: f64,
    /// G.
    pub shear: f64,
    /// σ_y.
    pub yield_stress: f64,
    /// H.
    pub hardening: f64,
    /// Thermal strain increment α ΔT.
    pub dth: f64,
}

impl Model for J2Step {
    #[inline(always)]
    fn update(&self, l: DMat2, v: &mut MaterialView, i: usize) {
        let g = self.shear;
        let st = v.stress[i];
        let tr_old = st.trace();
        let q0 = spin(l, self.dt);
        let t = elastic(l, self.dt, self.bulk, g, self.dth, &mut v.def[i], &st);
        let (txx, tyy, txy, tzz) = (t.xx, t.yy, t.xy, t.zz);
        let m = (txx + tyy + tzz) / 3.0;
        let s = [txx - m, tyy - m, tzz - m, txy];
        let ss = s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + 2.0 * s[3] * s[3];
        let q = (1.5 * ss).sqrt();
        let ep = v.plastic[i];
        let over = q - (self.yield_stress + self.hardening * ep);
        let scale = if over > 0.0 {
            let dg = over / (3.0 * g + self.hardening);
            let scale = 1.0 - 3.0 * g * dg / q;
            v.plastic[i] = ep + dg;
            // Plastic work σ̄:Δεᵖ with Δεᵖ = Δγ (3/2) s_trial/q_trial and σ̄ the mean of
            // the rotated old stress and the returned one: with the elastic energy taken
            // from the stress, this closes the energy balance of the midpoint rule.
            let [rxx, ryy, rxy] = rotate([st.xx, st.yy, st.xy], q0);
            let m0 = (rxx + ryy + st.zz) / 3.0;
            let s0 = [rxx - m0, ryy - m0, st.zz - m0, rxy];
            let old = 1.5 * (s0[0] * s[0] + s0[1] * s[1] + s0[2] * s[2] + 2.0 * s0[3] * s[3]) / q;
            let vol_now = v.vol0[i] * v.def[i].determinant();
            v.dissipated[i] += 0.5 * dg * (old + scale * q) * vol_now;
            scale
        } else {
            1.0
        };
        v.stress[i] = Stress {
            xx: m + scale * s[0],
            yy: m + scale * s[1],
            zz: m + scale * s[2],
            xy: scale * s[3],
        };
        if self.dth != 0.0 {
            thermal_work(v, i, tr_old, self.dth);
        }
    }
}

/// One Prony term's constants for a step of length dt. With x = dt/τ, A = 1 − e^(−x),
/// k = 2Gτ and a = k D′ the branch's steady stress, the exact update is
/// s⁺ = e^(−x) s + A k D′, and its dissipation ∫ s:s/(2Gτ) dt along that path is
/// (τ/2k) A(2 − A) s:s + τA² s:D′ + k τ (x − A − A²/2) D′:D′.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TermStep {
    /// e^(−dt/τ).
    pub decay: f64,
    /// A k: the branch stress per unit D′ gained over the step.
    pub gain: f64,
    /// Dissipation per s:s.
    pub diss_ss: f64,
    /// Dissipation per s:D′.
    pub diss_sd: f64,
    /// Dissipation per D′:D′.
    pub diss_dd: f64,
}

impl TermStep {
    /// The constants of `term` over `dt`.
    pub fn new(term: PronyTerm, dt: f64) -> Self {
        let (tau, k) = (term.time, 2.0 * term.shear * term.time);
        let x = dt / tau;
        let a = -(-x).exp_m1();
        // x − A − A²/2 = x³/3 − x⁴/4 + 7x⁵/60 − …: by its series where the closed form
        // cancels (relative error < 1e-9 either way).
        let rest = if x < 1e-3 {
            x * x * x * (1.0 / 3.0 - x / 4.0 + 7.0 * x * x / 60.0)
        } else {
            x - a - 0.5 * a * a
        };
        TermStep {
            decay: 1.0 - a,
            gain: a * k,
            diss_ss: 0.5 * tau * a * (2.0 - a) / k,
            diss_sd: tau * a * a,
            diss_dd: k * tau * rest,
        }
    }
}

/// s:t of two deviatoric tensors stored as (xx, yy, xy) with zz = −(xx + yy).
#[inline(always)]
fn branch_dot(s: [f64; 3], t: [f64; 3]) -> f64 {
    s[0] * t[0] + s[1] * t[1] + (s[0] + s[1]) * (t[0] + t[1]) + 2.0 * s[2] * t[2]
}

/// Generalized Maxwell step. Each branch is integrated exactly for a constant deviatoric
/// rate D′ over the step, sᵢ(t) = aᵢ + (sᵢ⁰ − aᵢ) e^(−t/τᵢ) with aᵢ = 2Gᵢτᵢ D′, and its
/// dissipation ∫ sᵢ:sᵢ/(2ηᵢ) dt is integrated exactly along that path ([`TermStep`]).
#[derive(Clone, Debug, PartialEq)]
pub struct MaxwellStep {
    /// Step (s).
    pub dt: f64,
    /// K.
    pub bulk: f64,
    /// G∞.
    pub shear: f64,
    /// Thermal strain increment α ΔT.
    pub dth: f64,
    /// Per Prony term.
    pub terms: Vec<TermStep>,
    /// Σ of the terms' dissipation per D′:D′.
    pub diss_dd: f64,
}

impl MaxwellStep {
    /// The step of a series of Prony `terms` over `dt`.
    pub fn new(dt: f64, bulk: f64, shear: f64, dth: f64, terms: &[PronyTerm]) -> Self {
        let terms: Vec<TermStep> = terms.iter().map(|t| TermStep::new(*t, dt)).collect();
        MaxwellStep {
            dt,
            bulk,
            shear,
            dth,
            diss_dd: terms.iter().map(|t| t.diss_dd).sum(),
            terms,
        }
    }
}

impl Model for MaxwellStep {
    #[inline(always)]
    fn update(&self, l: DMat2, v: &mut MaterialView, i: usize) {
        let dt = self.dt;
        advance(l, dt, &mut v.def[i]);
        let (dxx, dyy) = (l.x_axis.x, l.y_axis.y);
        let third = (dxx + dyy) / 3.0;
        // Deviatoric rate (xx, yy, xy); zz = −third.
        let dd = [dxx - third, dyy - third, 0.5 * (l.y_axis.x + l.x_axis.y)];
        let q = spin(l, dt);
        let st = v.stress[i];
        let tr_old = st.trace();
        let [mut xx, mut yy, mut xy] = rotate([st.xx, st.yy, st.xy], q);
        let vol = self.bulk * (3.0 * third * dt - 3.0 * self.dth);
        let g2 = 2.0 * self.shear * dt;
        xx += vol + g2 * dd[0];
        yy += vol + g2 * dd[1];
        xy += g2 * dd[2];
        let mut zz = st.zz + vol - g2 * third;
        let mut dissipated = self.diss_dd * branch_dot(dd, dd);
        let (mut olds, mut news) = ([0.0; 3], [0.0; 3]);
        let branches = &mut v.branches[i * v.width..][..self.terms.len()];
        for (t, b) in self.terms.iter().zip(branches.iter_mut()) {
            let old = rotate(*b, q);
            dissipated += t.diss_ss * branch_norm2(old) + t.diss_sd * branch_dot(old, dd);
            let new = [
                t.decay * old[0] + t.gain * dd[0],
                t.decay * old[1] + t.gain * dd[1],
                t.decay * old[2] + t.gain * dd[2],
            ];
            for c in 0..3 {
                olds[c] += old[c];
                news[c] += new[c];
            }
            *b = new;
        }
        xx += news[0] - olds[0];
        yy += news[1] - olds[1];
        xy += news[2] - olds[2];
        zz -= (news[0] + news[1]) - (olds[0] + olds[1]);
        v.dissipated[i] += dissipated * v.vol0[i] * v.def[i].determinant();
        v.stress[i] = Stress { xx, yy, xy, zz };
        if self.dth != 0.0 {
            thermal_work(v, i, tr_old, self.dth);
        }
    }
}

/// One material point's state outside the particle arrays: for tests, single-point
/// drivers and constitutive exploration.
#[derive(Clone, Debug, PartialEq)]
pub struct PointState {
    /// Reference volume.
    pub vol0: f64,
    /// Deformation gradient.
    pub def: DMat2,
    /// Stress.
    pub stress: Stress,
    /// Equivalent plastic strain.
    pub plastic: f64,
    /// Dissipated energy.
    pub dissipated: f64,
    /// Thermal work.
    pub thermal_work: f64,
    /// Maxwell branch stresses.
    pub branches: Vec<[f64; 3]>,
}

impl PointState {
    /// An undeformed, unstressed point of unit volume for `material`.
    pub fn new(material: &Material) -> Self {
        PointState {
            vol0: 1.0,
            def: DMat2::IDENTITY,
            stress: Stress::default(),
            plastic: 0.0,
            dissipated: 0.0,
            thermal_work: 0.0,
            branches: vec![[0.0; 3]; material.branches()],
        }
    }

    /// Advances the point by one step of `prepared` under the velocity gradient `l`.
    pub fn update(&mut self, prepared: &Prepared, l: DMat2) {
        let width = self.branches.len();
        let mut v = MaterialView {
            vol0: std::slice::from_ref(&self.vol0),
            def: std::slice::from_mut(&mut self.def),
            stress: std::slice::from_mut(&mut self.stress),
            plastic: std::slice::from_mut(&mut self.plastic),
            dissipated: std::slice::from_mut(&mut self.dissipated),
            thermal_work: std::slice::from_mut(&mut self.thermal_work),
            branches: &mut self.branches,
            width,
        };
        with_model!(prepared, m => m.update(l, &mut v, 0));
    }

    /// Runs `n` steps of length `dt` under a constant `l` and a temperature changing
    /// by `dtemp` per step.
    pub fn drive(&mut self, material: &Material, l: DMat2, dt: f64, dtemp: f64, n: usize) {
        let th = Thermal {
            start: 0.0,
            end: dtemp,
        };
        let p = material.prepare(dt, th);
        for _ in 0..n {
            self.update(&p, l);
        }
    }

    /// Stored energy.
    pub fn stored(&self, material: &Material) -> f64 {
        material.stored_energy(self.vol0, self.def, &self.stress, &self.branches)
    }
}

#[cfg(test)]
#[path = "models_tests.rs"]
mod tests;
