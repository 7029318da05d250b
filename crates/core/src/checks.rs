//! Pass/fail verification records, serialised into each run's
//! `summary.json`.

use std::fmt;

use serde::{Deserialize, Deserializer, Serialize};

/// One quantitative check of a simulation result against an expectation.
///
/// `kind` says how to read `expected` and `tolerance`, so a `summary.json`
/// can be judged without knowing which constructor made it:
///
/// | `kind`       | passes when                                   | `tolerance` is |
/// |--------------|-----------------------------------------------|----------------|
/// | `"relative"` | `|measured - expected| <= tolerance * |expected|` | relative (0.05 = 5 %) |
/// | `"absolute"` | `|measured - expected| <= tolerance`          | in the units of `measured` |
/// | `"at_most"`  | `measured <= expected` (`expected` is the limit) | always 0 |
/// | `"at_least"` | `measured >= expected` (`expected` is the limit) | always 0 |
///
/// A non-finite `measured` (a blown-up run) never passes. JSON has no NaN or
/// infinity: they are written as `null` and read back as NaN.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Check {
    /// What was checked, e.g. `"restitution coefficient"`.
    pub name: String,
    /// `"relative"`, `"absolute"`, `"at_most"` or `"at_least"`.
    pub kind: String,
    /// The value the simulation produced.
    #[serde(deserialize_with = "nullable_f64")]
    pub measured: f64,
    /// The reference value, or the limit for `at_most`/`at_least`.
    #[serde(deserialize_with = "nullable_f64")]
    pub expected: f64,
    /// Allowed deviation; see the table above for its meaning per kind.
    #[serde(deserialize_with = "nullable_f64")]
    pub tolerance: f64,
    /// Whether the check passed.
    pub pass: bool,
    /// Free-text context (reference, why the tolerance is what it is).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub note: Option<String>,
}

/// Reads `null` (how serde_json writes NaN and infinities) back as NaN, so a
/// summary of a failed run still loads.
fn nullable_f64<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

impl Check {
    fn make(
        name: &str,
        kind: &str,
        measured: f64,
        expected: f64,
        tolerance: f64,
        pass: bool,
    ) -> Self {
        Self {
            name: name.to_string(),
            kind: kind.to_string(),
            measured,
            expected,
            tolerance,
            pass,
            note: None,
        }
    }

    /// Passes if `|measured - expected| <= rel_tol * |expected|`. With
    /// `expected == 0` only an exact match passes; use [`Check::absolute`]
    /// for quantities that should vanish.
    pub fn relative(name: &str, measured: f64, expected: f64, rel_tol: f64) -> Self {
        let pass = all_finite(&[measured, expected, rel_tol])
            && (measured - expected).abs() <= rel_tol * expected.abs();
        Self::make(name, "relative", measured, expected, rel_tol, pass)
    }

    /// Passes if `|measured - expected| <= abs_tol`.
    pub fn absolute(name: &str, measured: f64, expected: f64, abs_tol: f64) -> Self {
        let pass =
            all_finite(&[measured, expected, abs_tol]) && (measured - expected).abs() <= abs_tol;
        Self::make(name, "absolute", measured, expected, abs_tol, pass)
    }

    /// Passes if `measured <= limit` (e.g. energy drift, overlap).
    pub fn at_most(name: &str, measured: f64, limit: f64) -> Self {
        let pass = measured.is_finite() && !limit.is_nan() && measured <= limit;
        Self::make(name, "at_most", measured, limit, 0.0, pass)
    }

    /// Passes if `measured >= limit` (e.g. packing fraction reached).
    pub fn at_least(name: &str, measured: f64, limit: f64) -> Self {
        let pass = measured.is_finite() && !limit.is_nan() && measured >= limit;
        Self::make(name, "at_least", measured, limit, 0.0, pass)
    }

    /// Attaches a note.
    pub fn with_note(mut self, note: &str) -> Self {
        self.note = Some(note.to_string());
        self
    }

    /// Relative deviation `|measured - expected| / |expected|` (infinite when
    /// `expected` is 0 and they differ), for reports.
    pub fn relative_error(&self) -> f64 {
        let d = (self.measured - self.expected).abs();
        if d == 0.0 {
            0.0
        } else {
            d / self.expected.abs()
        }
    }
}

fn all_finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// True if every check passed (and there is at least one: an empty list
/// usually means the run never got to its checks).
pub fn all_pass(checks: &[Check]) -> bool {
    !checks.is_empty() && checks.iter().all(|c| c.pass)
}

/// One console line, e.g.
/// `PASS  restitution: measured 0.801 expected 0.8 (relative tol 0.02)`.
impl fmt::Display for Check {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let verdict = if self.pass { "PASS" } else { "FAIL" };
        write!(f, "{verdict}  {}: measured {:e} ", self.name, self.measured)?;
        match self.kind.as_str() {
            "at_most" => write!(f, "<= limit {:e}", self.expected)?,
            "at_least" => write!(f, ">= limit {:e}", self.expected)?,
            kind => write!(
                f,
                "expected {:e} ({kind} tol {:e})",
                self.expected, self.tolerance
            )?,
        }
        if let Some(n) = &self.note {
            write!(f, " [{n}]")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative() {
        assert!(Check::relative("a", 1.04, 1.0, 0.05).pass);
        assert!(!Check::relative("a", 1.06, 1.0, 0.05).pass);
        assert!(Check::relative("a", -1.04, -1.0, 0.05).pass);
        assert!(!Check::relative("a", f64::NAN, 1.0, 0.05).pass);
        assert!(!Check::relative("a", 1e-9, 0.0, 0.05).pass);
        let c = Check::relative("a", 1.0, 1.0, 0.05);
        assert_eq!((c.kind.as_str(), c.tolerance), ("relative", 0.05));
    }

    #[test]
    fn absolute_and_limits() {
        assert!(Check::absolute("b", 0.1, 0.0, 0.1).pass);
        assert!(!Check::absolute("b", 0.11, 0.0, 0.1).pass);
        assert!(!Check::absolute("b", f64::INFINITY, 0.0, 0.1).pass);
        let m = Check::at_most("drift", 1e-3, 1e-2);
        assert!(m.pass && m.expected == 1e-2 && m.tolerance == 0.0);
        assert!(!Check::at_most("drift", f64::NAN, 1.0).pass);
        assert!(Check::at_most("drift", -5.0, f64::INFINITY).pass);
        assert!(Check::at_least("phi", 0.82, 0.8).pass);
        assert!(!Check::at_least("phi", 0.7, 0.8).pass);
        assert_eq!(Check::at_least("phi", 0.7, 0.8).kind, "at_least");
    }

    #[test]
    fn json_round_trip_including_nan_and_note() {
        let checks = vec![
            Check::relative("e", 0.81, 0.8, 0.02).with_note("Hertz"),
            Check::at_most("overlap", f64::NAN, 0.01),
        ];
        let s = serde_json::to_string(&checks).unwrap();
        assert!(s.contains("\"kind\":\"relative\""), "{s}");
        assert!(s.contains("\"note\":\"Hertz\""));
        assert_eq!(s.matches("note").count(), 1);
        let back: Vec<Check> = serde_json::from_str(&s).unwrap();
        assert_eq!(back[0], checks[0]);
        assert!(back[1].measured.is_nan() && !back[1].pass);
        assert!(all_pass(&back[..1]));
        assert!(!all_pass(&back));
        assert!(!all_pass(&[]));
    }

    #[test]
    fn display_and_relative_error() {
        let c = Check::relative("e", 0.81, 0.8, 0.02);
        let line = c.to_string();
        assert!(line.starts_with("PASS  e: measured 8.1e-1"), "{line}");
        assert!((c.relative_error() - 0.0125).abs() < 1e-12);
        assert!(Check::at_most("o", 2.0, 1.0)
            .to_string()
            .starts_with("FAIL"));
        assert_eq!(Check::absolute("z", 0.0, 0.0, 1.0).relative_error(), 0.0);
    }
}
