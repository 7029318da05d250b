//! What the engine asks of a contact law: the [`ContactLaw`] trait, which the linear law
//! ([`PairParams`], `crate::contact`) and the granular law ([`GranularParams`],
//! `crate::granular`) implement.
//!
//! A law is chosen once per material pair (a [`crate::PairTable`] of one law's
//! parameters) and the passes are generic over it, so each law's kernel is compiled into
//! its own loop, with no dispatch per contact. Beside the pair response, everything that
//! depends on the law asks it here: the elastic energy of the diagnostics
//! ([`ContactLaw::stored_energy`]), the stable time step of [`crate::timestep`]
//! ([`ContactLaw::stable_step`]) and the energy ledger's split of the dissipation
//! ([`ContactLaw::ledger_terms`]).

use crate::contact::PairParams;
use crate::granular::{self, GranularParams, Normal, Tangential};
use crate::material::Material;
use crate::math::{self, AngVector, Tangent, TangentOps, Vector};

/// One contact's geometry and motion.
#[derive(Clone, Copy, Debug)]
pub struct Contact {
    /// Unit normal from i towards j.
    pub n: Vector,
    /// Overlap δ > 0.
    pub overlap: f64,
    /// R_i R_j / (R_i + R_j) (a flat wall: R_i). Zero where the law does not read it
    /// ([`ContactLaw::CURVED`] false).
    pub r_eff: f64,
    /// m_i m_j / (m_i + m_j) (a wall: m_i).
    pub m_eff: f64,
    /// v_i − v_j.
    pub v: Vector,
    /// R_i ω_i + R_j ω_j.
    pub spin: AngVector,
    /// ω_i − ω_j. Zero where the law does not read it ([`ContactLaw::CURVED`] false).
    pub w_rel: AngVector,
}

/// What a contact does to its bodies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Response {
    /// Force on i (j gets the opposite).
    pub force: Vector,
    /// n × F_t: the tangential force's torque on i is its arm times this (the linear
    /// law: R_i; the granular law: R_i − δ/2), and on j likewise.
    pub moment: AngVector,
    /// The rolling and twisting couple on i (j gets the opposite).
    pub couple: AngVector,
    /// The normal force F_n (positive pushes apart), damping included.
    pub normal: f64,
}

/// The bodies whose contact a step bound is for: the lightest and the smallest particle
/// of a material.
#[derive(Clone, Copy, Debug)]
pub struct Body<'a> {
    /// Mass (kg; per unit thickness in 2D).
    pub mass: f64,
    /// Radius (m).
    pub radius: f64,
    /// The material.
    pub material: &'a Material,
}

/// A law's bound on the time step for one pair of bodies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StepBound {
    /// The pair is an oscillator of angular frequency ω and damping ratio ζ, which
    /// velocity Verlet integrates stably for ω Δt < 2(√(1 + ζ²) − ζ).
    Oscillator {
        /// ω (1/s): the stiffest of the pair's modes.
        omega: f64,
        /// ζ of the normal mode.
        zeta: f64,
    },
    /// The step must not exceed this time (s).
    Time(f64),
}

/// The energy ledger's terms for one contact over one step (J; per unit thickness in
/// 2D): see [`crate::ledger`] for what each holds. A law fills the terms of the springs
/// it has and leaves the others zero.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LedgerTerms {
    /// The normal and tangential dashpots' work.
    pub damping: f64,
    /// Coulomb sliding of the tangential spring.
    pub friction: f64,
    /// Energy the normal spring stores after the step.
    pub normal: f64,
    /// Energy the tangential spring stores after the step.
    pub tangential: f64,
    /// Energy the tangential spring stored before the step.
    pub tangential_before: f64,
    /// The tangential dashpot's share of `damping`.
    pub damping_tangential: f64,
    /// The rolling dashpot's work.
    pub rolling_damping: f64,
    /// Sliding at the rolling cap μ_r |F_n|.
    pub rolling_friction: f64,
    /// The twisting dashpot's work.
    pub twisting_damping: f64,
    /// Sliding at the twisting cap.
    pub twisting_friction: f64,
    /// Energy the rolling spring stores after the step.
    pub rolling: f64,
    /// Energy the rolling spring stored before the step.
    pub rolling_before: f64,
    /// Energy the twisting spring stores after the step.
    pub twisting: f64,
    /// Energy the twisting spring stored before the step.
    pub twisting_before: f64,
    /// Energy the springs lost without work (negative: gained): their stiffness changing
    /// with the contact radius, a spring rescaled or carried to a new length.
    pub softening: f64,
    /// Work the law's forces did on the bodies beyond what its springs and dashpots
    /// book, taken as a loss (negative: a gain): the tangential force turns the bodies
    /// about arms R − δ/2 but its slip is read with arms R.
    pub lever: f64,
    /// Work a moving wall did on the body (wall contacts only; laws leave it zero).
    pub work: f64,
}

/// What the ledger needs of a step's start that a [`Contact`] does not hold.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Prior {
    /// The overlap before the step's drift: R_i + R_j − |d + Δt v| (d = x_j − x_i, v the
    /// drift's velocity v_i − v_j), negative where the pair did not touch.
    pub overlap: f64,
    /// ω_i + ω_j over the step.
    pub omega_sum: AngVector,
}

/// A contact law: its per-pair parameters are the implementing type.
pub trait ContactLaw: Copy + Send + Sync + std::fmt::Debug {
    /// What one contact remembers from step to step.
    type History: Copy + Default + PartialEq + Send + Sync + std::fmt::Debug;
    /// How many numbers [`Self::History`] holds.
    const WIDTH: usize;
    /// Whether the response reads [`Contact::r_eff`] and [`Contact::w_rel`]; a pass for
    /// a law that does not may leave them zero and save gathering them.
    const CURVED: bool;
    /// Whether the law splits its dissipation for the energy ledger
    /// ([`ContactLaw::ledger_terms`]); a ledger is refused under a law that does not.
    const LEDGER: bool;

    /// Evaluates one touching contact and advances its history `h` by `dt` (`dt = 0`
    /// evaluates without advancing it, as a set-up evaluation).
    fn respond(&self, c: &Contact, h: &mut Self::History, dt: f64) -> Response;

    /// The elastic energy the contact stores at overlap δ with history `h`.
    fn stored_energy(&self, overlap: f64, r_eff: f64, h: &Self::History) -> f64;

    /// The stable-step bound for a contact of `a` with `b` (`None`: a wall, infinitely
    /// heavy and not turning).
    fn stable_step(&self, a: &Body, b: Option<&Body>) -> StepBound;

    /// The ledger's terms of a contact that [`ContactLaw::respond`] took from `before`
    /// to `after` over `dt`, answering `r`, from `prior` at the step's start; zero under
    /// a law without a ledger ([`ContactLaw::LEDGER`] false).
    #[inline(always)]
    fn ledger_terms(
        &self,
        _c: &Contact,
        _before: &Self::History,
        _after: &Self::History,
        _r: &Response,
        _dt: f64,
        _prior: &Prior,
    ) -> LedgerTerms {
        LedgerTerms::default()
    }

    /// The energy each spring of a contact stores at overlap δ with history `h`: the
    /// stored fields of [`LedgerTerms`] (`normal`, `tangential`, `rolling`, `twisting`),
    /// the others zero. They add up to [`ContactLaw::stored_energy`].
    fn stored_split(&self, overlap: f64, r_eff: f64, h: &Self::History) -> LedgerTerms;
}

/// The effective mass m_eff of a contact of `a` with `b` (`None`: a wall, m_eff = m_a)
/// and the inverse mass of its contact points' tangential motion, which carries
/// rotation: 1/m + r²/I per body, (1 + 1/f)/m with I = f m r² (nothing for a wall).
#[inline]
fn pair_masses(a: &Body, b: Option<&Body>) -> (f64, f64) {
    let fa = a.material.inertia_factor;
    match b {
        Some(b) => {
            let fb = b.material.inertia_factor;
            (
                1.0 / (1.0 / a.mass + 1.0 / b.mass),
                (1.0 + 1.0 / fa) / a.mass + (1.0 + 1.0 / fb) / b.mass,
            )
        }
        None => (a.mass, (1.0 + 1.0 / fa) / a.mass),
    }
}

impl ContactLaw for PairParams {
    type History = Tangent;
    const WIDTH: usize = math::TAN;
    const CURVED: bool = false;
    const LEDGER: bool = true;

    #[inline(always)]
    fn respond(&self, c: &Contact, h: &mut Tangent, dt: f64) -> Response {
        let f = crate::forces::contact_law(self, c.m_eff, c.n, c.overlap, c.v, c.spin, *h, dt);
        *h = f.shear;
        Response {
            force: -f.normal * c.n + math::tangent_vector(f.tangential, c.n),
            moment: math::moment(f.tangential, c.n),
            couple: AngVector::default(),
            normal: f.normal,
        }
    }

    /// ½ K_n δ² + ½ K_t |ξ|².
    #[inline]
    fn stored_energy(&self, overlap: f64, _r_eff: f64, h: &Tangent) -> f64 {
        0.5 * self.kn * overlap * overlap + h.quad(0.5 * self.kt)
    }

    /// The stiffest of the pair's normal mode (ω² = K_n / m_eff) and the tangential mode
    /// of its contact points (ω² = K_t times their inverse mass, [`pair_masses`]).
    #[inline]
    fn stable_step(&self, a: &Body, b: Option<&Body>) -> StepBound {
        let (m_eff, inv_t) = pair_masses(a, b);
        let wn = (self.kn / m_eff).sqrt();
        let wt = (self.kt * inv_t).sqrt();
        StepBound::Oscillator {
            omega: wn.max(wt),
            zeta: self.normal_dashpot(m_eff) / (2.0 * m_eff * wn),
        }
    }

    /// The split [`crate::ledger`] describes, from the law's own kinematics.
    #[inline(always)]
    fn ledger_terms(
        &self,
        c: &Contact,
        before: &Tangent,
        after: &Tangent,
        r: &Response,
        dt: f64,
        _prior: &Prior,
    ) -> LedgerTerms {
        let (n, v) = (c.n, c.v);
        let vn = v.dot(n);
        let vt = math::tangential_velocity(v, n, c.spin);
        let elastic = self.kn * c.overlap;
        // Sliding resets the spring; the tangential work less the spring's change is
        // then friction's, the capped dashpot's share included.
        let x0 = math::carry(*before, n);
        let sliding = (*after != x0 + vt * dt) as u8 as f64;
        let x1 = *after;
        let dash_t = vt.quad(self.gamma_t * c.m_eff) * dt;
        LedgerTerms {
            damping: (r.normal - elastic) * vn * dt + (1.0 - sliding) * dash_t,
            friction: sliding
                * (self.kt * (x1.dot(vt) * dt - 0.5 * (x1.dot(x1) - x0.dot(x0))) + dash_t),
            normal: 0.5 * elastic * c.overlap,
            tangential: x1.quad(0.5 * self.kt),
            tangential_before: x0.quad(0.5 * self.kt),
            damping_tangential: (1.0 - sliding) * dash_t,
            ..LedgerTerms::default()
        }
    }

    /// ½K_n δ² (none apart) and ½K_t |ξ|².
    fn stored_split(&self, overlap: f64, _r_eff: f64, h: &Tangent) -> LedgerTerms {
        LedgerTerms {
            normal: if overlap > 0.0 {
                0.5 * self.kn * overlap * overlap
            } else {
                0.0
            },
            tangential: h.quad(0.5 * self.kt),
            ..LedgerTerms::default()
        }
    }
}

/// The Rayleigh time of a sphere of radius r: π r √(ρ/G) / (0.1631 ν + 0.8766), G =
/// E / (2(1 + ν)) of its material (NaN when the material has no E).
pub fn rayleigh_time(radius: f64, m: &Material) -> f64 {
    let (e, nu) = (m.youngs.unwrap_or(f64::NAN), m.poisson.unwrap_or(0.0));
    let g = e / (2.0 * (1.0 + nu));
    std::f64::consts::PI * radius * (m.density / g).sqrt() / (0.1631 * nu + 0.8766)
}

impl ContactLaw for GranularParams {
    type History = crate::history::GranularHistory;
    const WIDTH: usize = granular::WIDTH;
    const CURVED: bool = true;
    const LEDGER: bool = true;

    #[inline(always)]
    fn respond(&self, c: &Contact, h: &mut Self::History, dt: f64) -> Response {
        granular::respond(self, c, h, dt, dt > 0.0)
    }

    #[inline]
    fn stored_energy(&self, overlap: f64, r_eff: f64, h: &Self::History) -> f64 {
        granular::stored_energy(self, overlap, r_eff, h)
    }

    /// The split `crate::granular_ledger` derives (docs/architecture.md, the ledger).
    #[inline]
    fn ledger_terms(
        &self,
        c: &Contact,
        before: &Self::History,
        after: &Self::History,
        r: &Response,
        dt: f64,
        prior: &Prior,
    ) -> LedgerTerms {
        crate::granular_ledger::terms(self, c, before, after, r, dt, prior)
    }

    #[inline]
    fn stored_split(&self, overlap: f64, r_eff: f64, h: &Self::History) -> LedgerTerms {
        granular::stored_split(self, overlap, r_eff, h)
    }

    /// Hertz: the shorter of the two spheres' Rayleigh times, [`rayleigh_time`] (the bound
    /// LIGGGHTS and YADE take a fraction of, the run's `safety`). A Hertz contact has no
    /// fixed stiffness — dF/dδ = (3/2) k_n √(R δ) grows with the overlap — so no
    /// oscillator bound holds at every overlap; the Rayleigh time, the time a surface
    /// wave takes to cross the sphere, does not depend on the speed of the impacts,
    /// which the set-up does not know, and for the impacts of the Chung & Ooi tests
    /// (glass, R 10 mm, 20 m/s closing) it sits below the oscillator bound at the
    /// impact's largest overlap (1.3e-5 s against 2/ω = 2.0e-5 s). Hooke: the linear
    /// oscillator's normal and tangential modes as [`PairParams`]'s (the linear spring
    /// k_t; Mindlin's a·k_t at a = R_eff), damped by η_n at a = R_eff (an upper bound on
    /// the contact radius, so on the viscoelastic dashpot).
    fn stable_step(&self, a: &Body, b: Option<&Body>) -> StepBound {
        if self.normal == Normal::HertzMaterial {
            let t = rayleigh_time(a.radius, a.material);
            return StepBound::Time(b.map_or(t, |b| t.min(rayleigh_time(b.radius, b.material))));
        }
        let (m_eff, inv_t) = pair_masses(a, b);
        let r_eff = b.map_or(a.radius, |b| a.radius * b.radius / (a.radius + b.radius));
        let kt = match self.tangential {
            Tangential::LinearHistory => self.kt,
            Tangential::Mindlin | Tangential::MindlinRescale => self.kt * r_eff,
        };
        let wn = (self.kn / m_eff).sqrt();
        let wt = (kt * inv_t).sqrt();
        let eta_n = self.damp
            * match self.damping {
                granular::Damping::Velocity => 1.0,
                granular::Damping::MassVelocity => m_eff,
                granular::Damping::Viscoelastic => r_eff * m_eff,
                granular::Damping::Tsuji | granular::Damping::Restitution => {
                    (m_eff * self.kn).sqrt()
                }
            };
        StepBound::Oscillator {
            omega: wn.max(wt),
            zeta: eta_n / (2.0 * m_eff * wn),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::granular::Damping;
    use crate::{ContactModel, Domain, EnergyLedger, PairTable, Particles, Setup, State};

    fn glass() -> Material {
        Material {
            name: "glass".into(),
            density: 2800.0,
            youngs: Some(48e9),
            poisson: Some(0.2),
            restitution: None,
            friction: None,
            inertia_factor: 0.4,
        }
    }

    /// Two particles of radii `r` in an open box, under `law` when given (else the
    /// linear law of `model`).
    fn pair(law: Option<GranularParams>, model: ContactModel, r: [f64; 2]) -> (Setup, State) {
        let mut hi = Vector::ZERO;
        for a in 0..math::DIM {
            hi[a] = 1.0;
        }
        let domain = Domain {
            lo: -hi,
            hi,
            periodic: [false; math::DIM],
        };
        let mut setup = Setup::new(domain, vec![glass()], model, vec![], Vector::ZERO, 1e-3)
            .expect("a valid set-up");
        setup.granular = law.map(|l| PairTable::from_fn(1, |_, _| l));
        let mut p = Particles::default();
        let mut at = Vector::ZERO;
        for (k, &radius) in r.iter().enumerate() {
            at[0] = (2 * k) as f64 * 0.0099;
            let mut v = Vector::ZERO;
            v[0] = 1.0 - 2.0 * k as f64;
            p.push(at, radius, 2800.0, 0.4, 0, v, AngVector::default());
        }
        let state = State::new(&setup, p);
        (setup, state)
    }

    fn hooke() -> ContactModel {
        ContactModel::HookeHistory {
            kn: 1e6,
            kt: 5e5,
            gamma_n: 0.0,
            gamma_t: 0.0,
            mu: 0.5,
            limit_damping: false,
        }
    }

    fn hertz() -> GranularParams {
        GranularParams::lammps(
            Normal::HertzMaterial,
            48e9,
            Damping::Tsuji,
            0.9,
            0.2,
            Tangential::Mindlin,
            None,
            1.0,
            0.3,
        )
    }

    #[test]
    fn hertz_is_bounded_by_the_smaller_spheres_rayleigh_time() {
        let (setup, s) = pair(Some(hertz()), hooke(), [0.01, 0.005]);
        let dt = crate::timestep::critical_dt(&setup, &s.particles);
        let want = rayleigh_time(0.005, &glass());
        assert_eq!(dt, want);
        // G = 20 GPa: π r √(ρ/G) / 0.9092.
        let by_hand = std::f64::consts::PI * 0.005 * (2800.0f64 / 20e9).sqrt() / 0.90922;
        assert!((dt / by_hand - 1.0).abs() < 1e-12, "{dt} vs {by_hand}");
    }

    #[test]
    fn linear_bound_is_the_stiffest_undamped_mode() {
        let (setup, s) = pair(None, hooke(), [0.01, 0.01]);
        let dt = crate::timestep::critical_dt(&setup, &s.particles);
        let m = s.particles.mass(0);
        // Tangential mode: k_t (1 + 1/0.4) 2/m = 3.5 k_n / m against the normal 2 k_n / m.
        let want = 2.0 / (5e5 * 2.0 * 3.5 / m).sqrt();
        assert!((dt / want - 1.0).abs() < 1e-12, "{dt} vs {want}");
        // The granular law's Hooke gives the same bound for the same springs.
        let mut law = hertz();
        (law.normal, law.tangential, law.kn, law.kt) =
            (Normal::Hooke, Tangential::LinearHistory, 1e6, 5e5);
        law.damping = Damping::Velocity;
        law.damp = 0.0;
        let (setup, s) = pair(Some(law), hooke(), [0.01, 0.01]);
        let granular = crate::timestep::critical_dt(&setup, &s.particles);
        assert!(
            (granular / want - 1.0).abs() < 1e-12,
            "{granular} vs {want}"
        );
    }

    #[test]
    fn the_granular_law_keeps_the_ledger() {
        let (setup, mut s) = pair(Some(hertz()), hooke(), [0.01, 0.01]);
        let l = EnergyLedger::starting(&setup, &s).expect("the granular law keeps a ledger");
        // Started on the stored energy the diagnostics measure.
        let d = crate::diagnostics::measure(&setup, &s);
        assert_eq!(l.stored(), d.elastic);
        crate::ledger_sums::start(&setup, &mut s).expect("the granular law keeps a ledger");
        crate::step(&setup, &mut s, 1e-7);
        let l = crate::ledger_sums::figures(&s).unwrap();
        assert!(l.total().is_finite() && l.damping > 0.0, "{l:?}");
    }

    #[test]
    fn the_elastic_energy_is_the_laws() {
        let law = hertz();
        let (setup, s) = pair(Some(law), hooke(), [0.01, 0.01]);
        let d = crate::diagnostics::measure(&setup, &s);
        // Overlap 0.0002 m, R_eff 0.005 m: (2/5) k_n √(R δ) δ².
        let overlap: f64 = 0.02 - 0.0198;
        let want = 0.4 * law.kn * (0.005 * overlap).sqrt() * overlap * overlap;
        assert!(
            (d.elastic / want - 1.0).abs() < 1e-9,
            "{} vs {want}",
            d.elastic
        );
    }
}
