//! Rigid bodies whose prescribed velocity changes over time (`velocity_table`): the
//! table, its validation, and the velocity the engine is given for each step.

use glam::DVec2;
use grains_core::input::InputError;
use grains_core::table;

/// A velocity history: rows `[t, vx, vy]` with strictly increasing times, linear in
/// between, held before the first row and after the last.
#[derive(Clone, Debug, PartialEq)]
pub struct VelocityTable {
    rows: Vec<[f64; 3]>,
}

impl VelocityTable {
    /// Validates `rows` (`key` is where the table sits in the scenario).
    pub fn new(key: &str, rows: &[[f64; 3]]) -> Result<Self, InputError> {
        table::validate(key, rows, "[t, vx, vy] row")?;
        Ok(VelocityTable {
            rows: rows.to_vec(),
        })
    }

    /// v(t).
    pub fn at(&self, t: f64) -> DVec2 {
        let [_, vx, vy] = table::at(&self.rows, t);
        DVec2::new(vx, vy)
    }

    /// The velocity of a step from `t` to `t + dt`: its midpoint value, so the body's
    /// displacement over the step is second-order accurate.
    pub fn over_step(&self, t: f64, dt: f64) -> DVec2 {
        self.at(t + 0.5 * dt)
    }
}
