//! Prescribed temperature of a body over time. The body's material turns each step's
//! temperature change into an isotropic thermal strain α ΔT (three-dimensional, so in
//! plane strain the confined out-of-plane direction carries σ_zz).

use grains_core::input::InputError;
use serde::{Deserialize, Serialize};

/// A body's temperature T(t) (K, or any consistent unit of the materials' α).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "history", rename_all = "snake_case", deny_unknown_fields)]
pub enum TemperatureHistory {
    /// T(t) = initial + rate·t.
    Rate {
        /// Temperature at t = 0.
        #[serde(default)]
        initial: f64,
        /// dT/dt (per s).
        rate: f64,
    },
    /// Piecewise linear through `(time, temperature)` points with strictly increasing
    /// times; held at the first value before the first time and at the last after.
    Table {
        /// `[time, temperature]` pairs.
        points: Vec<[f64; 2]>,
    },
}

impl TemperatureHistory {
    /// T(t).
    pub fn at(&self, t: f64) -> f64 {
        match self {
            TemperatureHistory::Rate { initial, rate } => initial + rate * t,
            TemperatureHistory::Table { points } => grains_core::table::at(points, t)[1],
        }
    }

    /// Finite numbers; a table needs at least one point and strictly increasing times.
    /// `key` is where the history sits in the scenario (e.g. `body[2].temperature`).
    pub fn validate(&self, key: &str) -> Result<(), InputError> {
        match self {
            TemperatureHistory::Rate { initial, rate } => {
                for (name, v) in [("initial", initial), ("rate", rate)] {
                    if !v.is_finite() {
                        return Err(InputError::new(
                            format!("{key}.{name}"),
                            v,
                            "must be a finite number",
                        ));
                    }
                }
            }
            TemperatureHistory::Table { points } => grains_core::table::validate(
                &format!("{key}.points"),
                points,
                "[time, temperature] pair",
            )?,
        }
        Ok(())
    }
}

/// The temperature seen by one stress update of a body, from `t0` to `t1`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Thermal {
    /// T(t0).
    pub start: f64,
    /// T(t1).
    pub end: f64,
}

impl Thermal {
    /// Over `[t0, t1]` under `history` (none: constant temperature 0).
    pub fn over(history: Option<&TemperatureHistory>, t0: f64, t1: f64) -> Self {
        match history {
            Some(h) => Thermal {
                start: h.at(t0),
                end: h.at(t1),
            },
            None => Thermal::default(),
        }
    }

    /// T(t1) − T(t0).
    pub fn change(&self) -> f64 {
        self.end - self.start
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn histories() {
        let r = TemperatureHistory::Rate {
            initial: 300.0,
            rate: -2.0,
        };
        assert_eq!(r.at(5.0), 290.0);
        let t = TemperatureHistory::Table {
            points: vec![[0.0, 1.0], [2.0, 3.0], [4.0, 3.0]],
        };
        assert_eq!(t.at(-1.0), 1.0);
        assert_eq!(t.at(1.0), 2.0);
        assert_eq!(t.at(3.0), 3.0);
        assert_eq!(t.at(10.0), 3.0);
        assert!(t.validate("body[0].temperature").is_ok());
        let th = Thermal::over(Some(&t), 0.5, 1.5);
        assert!((th.change() - 1.0).abs() < 1e-15);
        assert_eq!(Thermal::over(None, 0.0, 1.0).change(), 0.0);
    }

    #[test]
    fn bad_tables_name_the_key() {
        let t = TemperatureHistory::Table {
            points: vec![[0.0, 1.0], [2.0, 3.0], [1.0, 3.0]],
        };
        let e = t.validate("body[1].temperature").unwrap_err();
        assert_eq!(e.key, "body[1].temperature.points[2]");
        assert!(e.allowed.contains("increase"), "{e}");
        let t = TemperatureHistory::Table { points: vec![] };
        assert!(t.validate("k").is_err());
        let r = TemperatureHistory::Rate {
            initial: 0.0,
            rate: f64::NAN,
        };
        assert_eq!(r.validate("k").unwrap_err().key, "k.rate");
    }
}
