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
//!   contact law forgets its history, as LAMMPS's does), counted once when it goes.
//!
//! The stored contact energy is a state function (½K_n δ² + ½K_t ξ² summed,
//! [`diagnostics::measure`](crate::diagnostics::measure)'s `elastic`). Work in = kinetic
//! change + stored change + the ledger, up to the integrator's error (first order in Δt
//! for sliding, whose slip is read at the half step). Wall contacts are not in the
//! ledger.
//!
//! The pair pass computes the terms beside the forces, from the same values, in a
//! version of the pass compiled for it ([`Tally`]): without the ledger the pass is the
//! code it was, and with it the forces and the state are the same bit for bit.

use std::ops::AddAssign;

/// Energy the pair contacts have dissipated since the ledger was started (J per unit
/// thickness).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnergyLedger {
    /// Work of the normal and tangential dashpots.
    pub damping: f64,
    /// Coulomb sliding.
    pub friction: f64,
    /// Tangential springs dropped as their contacts opened.
    pub springs_released: f64,
}

impl EnergyLedger {
    /// Everything dissipated.
    pub fn total(&self) -> f64 {
        self.damping + self.friction + self.springs_released
    }
}

impl AddAssign for EnergyLedger {
    fn add_assign(&mut self, o: Self) {
        self.damping += o.damping;
        self.friction += o.friction;
        self.springs_released += o.springs_released;
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
