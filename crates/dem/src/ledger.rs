//! Where the particle contacts' energy goes: the energy ledger the pair pass keeps when
//! asked to ([`State::ledger`](crate::State::ledger) is `Some`).
//!
//! Per touching pair and step Δt (v_n the approach speed, v_t the sliding speed, both at
//! the half step the forces are evaluated with):
//!
//! * **damping**: the dashpots' work, (F_n − K_n δ)·v_n Δt, plus c_t v_t² Δt while the
//!   contact sticks. The first term is c_n v_n² Δt, or with `limit_damping` what the
//!   clamp at zero withholds;
//! * **friction**: on a step where the trial force exceeds μF_n and the spring is reset
//!   to ξ (so that −F_t = K_t ξ + c_t v_t), the tangential work −F_t v_t Δt less the
//!   spring's change ½K_t(ξ² − ξ_old²): the Coulomb cap bounds the force, the tangential
//!   dashpot's share included; zero while the contact sticks;
//! * **springs released**: ½K_t ξ² of a tangential spring whose contact has opened (the
//!   contact law forgets its history, as LAMMPS's does), counted once when it goes: the
//!   tangential energy the touching pairs held after the last pass, less what the pairs
//!   touching now held before this one.
//!
//! It also keeps the energy stored in the touching pairs' springs after the pass
//! (½K_n δ² and ½K_t ξ² summed). Work in = kinetic change + stored change + the
//! dissipation, up to the integrator's error (first order in Δt for sliding, whose slip
//! is read at the half step). Started on a state whose springs are not all zero, it
//! takes them in with [`EnergyLedger::starting`].
//!
//! Wall contacts are booked by the same terms (the wall a body of infinite mass that
//! does not turn), their springs kept apart ([`EnergyLedger::walls`]) so that each
//! pass's released springs are told from its own contacts'. A moving wall works on the
//! grains: F·v_w Δt per contact (F the force on the grain, v_w the wall's surface
//! velocity at the contact point), booked as `wall_work`, work in.
//!
//! Under the granular law (`crate::granular_ledger`) the same terms hold with the
//! law's stiffnesses (Hertz's normal spring, Mindlin's k_t a), the rolling and twisting
//! springs are booked as the tangential one is, and two terms name what the law does
//! without work: `softening` (a spring's energy changed by its stiffness following the
//! contact radius, or by `mindlin_rescale`) and `lever` (the tangential force's arms
//! R − δ/2 against the R its slip is read with). docs/architecture.md (*The energy
//! ledger*) derives each.
//!
//! The pair pass computes the terms beside the forces, from the same values, in a
//! version of the pass compiled for it ([`Tally`]): without the ledger the pass is the
//! code it was, and with it the forces and the state are the same bit for bit.
//!
//! A run does not keep an [`EnergyLedger`] as it goes: each particle keeps its own
//! running ledger (its row's terms added pass after pass, [`crate::ledger_sums`]), and
//! the figures here are the exact sums of those over the particles (and the ranks),
//! rounded, made only when a sample, the summary or a checkpoint asks. So the figures
//! are the same bits on any rank count with nothing sent per step.

use crate::granular::GranularParams;
use crate::law::{ContactLaw, LedgerTerms};
use crate::math::TangentOps;
use crate::setup::Setup;
use crate::step::State;
use std::ops::AddAssign;

/// A ledger asked of a law that does not split its dissipation (the granular law).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "the energy ledger is kept under the linear contact law only: the granular law \
     (Hertz, Mindlin) does not split its dissipation"
)]
pub struct LedgerRefused;

/// Energy the pair contacts have dissipated since the ledger was started, and what their
/// springs hold now (J per unit thickness). The rolling, twisting and non-work terms are
/// the granular law's (zero under the linear law).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnergyLedger {
    /// Work of the normal and tangential dashpots.
    pub damping: f64,
    /// Coulomb sliding.
    pub friction: f64,
    /// Springs (tangential, rolling, twisting) dropped as their contacts opened.
    pub springs_released: f64,
    /// ½K_n δ² of the touching pairs after the last pass (Hertz: (2/5) k_n a δ²).
    pub stored_normal: f64,
    /// ½K_t ξ² of the touching pairs after the last pass.
    pub stored_tangential: f64,
    /// The tangential dashpot's share of `damping`.
    pub damping_tangential: f64,
    /// Work of the rolling dashpots.
    pub rolling_damping: f64,
    /// Sliding at the rolling caps.
    pub rolling_friction: f64,
    /// Work of the twisting dashpots.
    pub twisting_damping: f64,
    /// Sliding at the twisting caps.
    pub twisting_friction: f64,
    /// Energy the springs lost without work as the law changed their stiffness or
    /// length (negative: gained; [`LedgerTerms::softening`]).
    pub softening: f64,
    /// Work the tangential forces did beyond the booked, taken as a loss
    /// ([`LedgerTerms::lever`]).
    pub lever: f64,
    /// ½k_r |ξ_r|² of the touching pairs after the last pass.
    pub stored_rolling: f64,
    /// ½k_tw θ² of the touching pairs after the last pass.
    pub stored_twisting: f64,
    /// What the wall contacts' springs hold after the last wall pass.
    pub walls: Springs,
    /// Work the moving walls did on the grains (J; work in, not dissipated).
    pub wall_work: f64,
}

/// The energy the springs of one kind of contact hold (J; per unit thickness in 2D).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Springs {
    /// Normal springs.
    pub normal: f64,
    /// Tangential springs.
    pub tangential: f64,
    /// Rolling springs.
    pub rolling: f64,
    /// Twisting springs.
    pub twisting: f64,
}

impl Springs {
    /// All of it.
    pub fn total(&self) -> f64 {
        self.normal + self.tangential + self.rolling + self.twisting
    }
}

impl EnergyLedger {
    /// Everything the contacts took out of kinetic and stored energy: what they
    /// dissipated ([`EnergyLedger::dissipated`]) and the law's changes without work
    /// (`softening`, `lever`).
    pub fn total(&self) -> f64 {
        self.dissipated() + self.softening + self.lever
    }

    /// Everything dissipated: dashpots, Coulomb caps and dropped springs.
    pub fn dissipated(&self) -> f64 {
        self.damping
            + self.friction
            + self.springs_released
            + self.rolling_damping
            + self.rolling_friction
            + self.twisting_damping
            + self.twisting_friction
    }

    /// Energy stored in the springs, the pairs' and the walls'.
    pub fn stored(&self) -> f64 {
        self.stored_normal
            + self.stored_tangential
            + self.stored_rolling
            + self.stored_twisting
            + self.walls.total()
    }

    /// A ledger started on `s`: nothing dissipated yet, its springs' energy stored;
    /// refused under a law that does not split its dissipation
    /// ([`ContactLaw::LEDGER`]). The sum of [`EnergyLedger::starting_rows`].
    pub fn starting(setup: &Setup, s: &State) -> Result<Self, LedgerRefused> {
        let mut sums = crate::ledger_sums::LedgerSums::default();
        for row in Self::starting_rows(setup, s)? {
            sums.add(&row);
        }
        Ok(sums.figures())
    }

    /// Each particle's part of [`EnergyLedger::starting`], as its words
    /// ([`EnergyLedger::to_words`]): the springs of its row (its pairs with higher ids)
    /// and of its wall contacts.
    pub fn starting_rows(
        setup: &Setup,
        s: &State,
    ) -> Result<Vec<[f64; LEDGER_WORDS]>, LedgerRefused> {
        if setup.granular.is_some() && !GranularParams::LEDGER {
            return Err(LedgerRefused);
        }
        let p = &s.particles;
        let list = &s.contacts;
        let mut rows = Vec::with_capacity(p.len());
        for i in 0..p.len() {
            let mut l = EnergyLedger::default();
            for e in list.row[i] as usize..list.row[i + 1] as usize {
                let j = list.nbr[e] as usize;
                let (mi, mj) = (p.material[i] as usize, p.material[j] as usize);
                let dist = setup.domain.min_image(p.pos[j] - p.pos[i]).length();
                let overlap = p.radius[i] + p.radius[j] - dist;
                let Some(table) = &setup.granular else {
                    let pp = setup.pairs.get(mi, mj);
                    if overlap > 0.0 {
                        l.stored_normal += 0.5 * pp.kn * overlap * overlap;
                    }
                    l.stored_tangential += list.shear[e].quad(0.5 * pp.kt);
                    continue;
                };
                if overlap > 0.0 {
                    let r_eff = p.radius[i] * p.radius[j] / (p.radius[i] + p.radius[j]);
                    let h = list.granular(e).unwrap_or_default();
                    let st = table.get(mi, mj).stored_split(overlap, r_eff, &h);
                    l.stored_normal += st.normal;
                    l.stored_tangential += st.tangential;
                    l.stored_rolling += st.rolling;
                    l.stored_twisting += st.twisting;
                }
            }
            l.walls = wall_springs(setup, s, i);
            rows.push(l.to_words());
        }
        Ok(rows)
    }

    /// Its numbers in a fixed order, for a checkpoint ([`EnergyLedger::from_words`]).
    pub fn to_words(&self) -> [f64; LEDGER_WORDS] {
        let w = &self.walls;
        [
            self.damping,
            self.friction,
            self.springs_released,
            self.stored_normal,
            self.stored_tangential,
            self.damping_tangential,
            self.rolling_damping,
            self.rolling_friction,
            self.twisting_damping,
            self.twisting_friction,
            self.softening,
            self.lever,
            self.stored_rolling,
            self.stored_twisting,
            w.normal,
            w.tangential,
            w.rolling,
            w.twisting,
            self.wall_work,
        ]
    }

    /// The ledger of [`EnergyLedger::to_words`].
    pub fn from_words(w: &[f64; LEDGER_WORDS]) -> Self {
        EnergyLedger {
            damping: w[0],
            friction: w[1],
            springs_released: w[2],
            stored_normal: w[3],
            stored_tangential: w[4],
            damping_tangential: w[5],
            rolling_damping: w[6],
            rolling_friction: w[7],
            twisting_damping: w[8],
            twisting_friction: w[9],
            softening: w[10],
            lever: w[11],
            stored_rolling: w[12],
            stored_twisting: w[13],
            walls: Springs {
                normal: w[14],
                tangential: w[15],
                rolling: w[16],
                twisting: w[17],
            },
            wall_work: w[18],
        }
    }
}

/// The energy particle `i`'s wall contacts' springs in `s` hold (as
/// `crate::diagnostics` counts them: a wall is flat, R_eff the particle's radius).
fn wall_springs(setup: &Setup, s: &State, i: usize) -> Springs {
    let (p, list) = (&s.particles, &s.contacts);
    let mut out = Springs::default();
    for o in crate::walls::overlapping_walls(setup, p, i) {
        let (k, pair) = (o.slot, o.materials);
        let st = match &setup.granular {
            Some(table) => {
                let h = list.wall_history.try_get(k).unwrap_or_default();
                table
                    .get(pair.0, pair.1)
                    .stored_split(o.overlap, p.radius[i], &h)
            }
            None => {
                let xi = list.wall_shear.get(k).copied().unwrap_or_default();
                setup
                    .pairs
                    .get(pair.0, pair.1)
                    .stored_split(o.overlap, p.radius[i], &xi)
            }
        };
        out.normal += st.normal;
        out.tangential += st.tangential;
        out.rolling += st.rolling;
        out.twisting += st.twisting;
    }
    out
}

/// What one pass adds up: the law's [`LedgerTerms`] summed per particle (its row),
/// then taken into the particles' exact sums ([`crate::ledger_sums`]).
pub(crate) type PassTally = LedgerTerms;

/// Numbers in an [`EnergyLedger`] ([`EnergyLedger::to_words`]).
pub const LEDGER_WORDS: usize = 19;

/// Numbers in one [`PassTally`].
const WORDS: usize = 17;

impl PassTally {
    /// Its numbers in a fixed order.
    fn words(&self) -> [f64; WORDS] {
        [
            self.damping,
            self.friction,
            self.normal,
            self.tangential,
            self.tangential_before,
            self.damping_tangential,
            self.rolling_damping,
            self.rolling_friction,
            self.twisting_damping,
            self.twisting_friction,
            self.rolling,
            self.rolling_before,
            self.twisting,
            self.twisting_before,
            self.softening,
            self.lever,
            self.work,
        ]
    }

    /// The tally of [`PassTally::words`].
    fn from_words(w: [f64; WORDS]) -> Self {
        PassTally {
            damping: w[0],
            friction: w[1],
            normal: w[2],
            tangential: w[3],
            tangential_before: w[4],
            damping_tangential: w[5],
            rolling_damping: w[6],
            rolling_friction: w[7],
            twisting_damping: w[8],
            twisting_friction: w[9],
            rolling: w[10],
            rolling_before: w[11],
            twisting: w[12],
            twisting_before: w[13],
            softening: w[14],
            lever: w[15],
            work: w[16],
        }
    }
}

impl AddAssign for PassTally {
    fn add_assign(&mut self, o: Self) {
        let (a, b) = (self.words(), o.words());
        *self = PassTally::from_words(std::array::from_fn(|k| a[k] + b[k]));
    }
}

/// Whether a pair pass keeps the ledger, decided at compile time so that the pass
/// without it does no ledger work at all.
pub(crate) trait Tally: Sync {
    /// Keep it.
    const ON: bool;
}

/// The pass without the ledger.
pub(crate) struct Off;

impl Tally for Off {
    const ON: bool = false;
}

/// The pass with the ledger.
pub(crate) struct On;

impl Tally for On {
    const ON: bool = true;
}
