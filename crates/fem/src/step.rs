//! One time step of a free charge: `kick_drift → stress_forces → kick`. A coupled run
//! calls the same stages itself and adds its contact forces to `nodes.f_ext` before the
//! closing kick.

use crate::integrate::{kick, kick_drift};
use crate::setup::FemSetup;
use crate::state::Charge;
use crate::stress::{stress_forces, Breakdown};

/// Advances the charge by `dt` (at most [`Charge::next_dt`]).
pub fn step(setup: &FemSetup, c: &mut Charge, dt: f64) -> Result<(), Breakdown> {
    kick_drift(c, dt);
    stress_forces(setup, c, dt)?;
    kick(setup, c, dt);
    Ok(())
}
