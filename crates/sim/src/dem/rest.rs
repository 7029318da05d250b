//! Stops a run once its bed has come to rest: the kinetic energy stays below a fraction
//! of Σ m|g|d̄ (the energy of lifting every particle by one mean diameter) for a while.

use super::Dem;
use crate::driver::{Flow, Observer, Status};
use grains_dem::diagnostics::Diagnostics;
use serde::{Deserialize, Serialize};

/// The rest rule.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RestDetector {
    /// Kinetic energy below which the bed counts as still (J/m).
    limit: f64,
    /// How long it must stay so (s).
    hold: f64,
    /// Since when it has (s).
    since: Option<f64>,
}

impl RestDetector {
    /// The rule for `sim`: still below `ratio` × Σ m|g|d̄ for `hold` seconds.
    pub fn new(sim: &Dem, ratio: f64, hold: f64) -> Self {
        let p = &sim.state.particles;
        let n = p.len();
        let mean_d = 2.0 * p.radius.iter().sum::<f64>() / n as f64;
        let weight: f64 = (0..n).map(|i| p.mass(i)).sum::<f64>() * sim.setup.gravity.length();
        Self::with_limit(ratio * weight * mean_d, hold)
    }

    /// The rule: kinetic energy below `limit` for `hold` seconds.
    pub fn with_limit(limit: f64, hold: f64) -> Self {
        RestDetector {
            limit,
            hold,
            since: None,
        }
    }

    /// Judges a sample at `time` with this kinetic energy.
    pub fn judge(&mut self, time: f64, kinetic: f64) -> Flow {
        if kinetic < self.limit {
            let since = *self.since.get_or_insert(time);
            if time - since >= self.hold {
                return Flow::Stop(Status::AtRest);
            }
        } else {
            self.since = None;
        }
        Flow::Continue
    }
}

impl Observer<Dem> for RestDetector {
    fn on_sample(&mut self, sim: &Dem, d: &Diagnostics) -> anyhow::Result<Flow> {
        Ok(self.judge(sim.state.time, d.kinetic()))
    }

    fn save(&self) -> Option<(&'static str, toml::Value)> {
        toml::Value::try_from(self).ok().map(|v| ("rest", v))
    }

    fn restore(&mut self, state: toml::Value) -> anyhow::Result<()> {
        *self = state.try_into()?;
        Ok(())
    }
}
