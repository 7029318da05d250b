//! Rejected input: one line naming the key, the value and what is allowed.

/// A rejected input value.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{key} = {value}: {allowed}")]
pub struct FemError {
    /// Dotted key path in the scenario.
    pub key: String,
    /// The offending value, as text.
    pub value: String,
    /// What would be accepted.
    pub allowed: String,
}

impl FemError {
    /// Builds an error from its three parts.
    pub fn new(
        key: impl Into<String>,
        value: impl Into<String>,
        allowed: impl Into<String>,
    ) -> Self {
        FemError {
            key: key.into(),
            value: value.into(),
            allowed: allowed.into(),
        }
    }
}

/// A number as the user would have written it: plain near 1, scientific far from it.
pub fn shown(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || (1e-3..1e6).contains(&a) || !a.is_finite() {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// `Ok` when `v` is finite and strictly positive.
pub fn positive(key: &str, v: f64) -> Result<(), FemError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(FemError::new(key, shown(v), "must be a finite number > 0"))
    }
}

/// `Ok` when `v` is finite and not negative.
pub fn non_negative(key: &str, v: f64) -> Result<(), FemError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(FemError::new(key, shown(v), "must be a finite number >= 0"))
    }
}
