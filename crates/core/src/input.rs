//! Rejected input, the same way everywhere: one line naming the key, the value and what
//! is allowed (`run.dt = 2e-6: above the stable limit 1.3e-6 s`), and one formatter for
//! files that are not valid TOML or do not fit their schema.
//!
//! Engines and the packing generator report what they reject as an [`InputError`]
//! with the key of their own input; the scenario layer that feeds them maps those keys
//! to where the value sits in the user's file ([`InputError::map_key`]).

use serde::de::DeserializeOwned;

/// A rejected input value.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{key} = {value}: {allowed}")]
pub struct InputError {
    /// Dotted key path in the input file.
    pub key: String,
    /// The offending value, as text.
    pub value: String,
    /// What would be accepted.
    pub allowed: String,
}

impl InputError {
    /// Builds an error from its three parts.
    pub fn new(key: impl Into<String>, value: impl Shown, allowed: impl Into<String>) -> Self {
        InputError {
            key: key.into(),
            value: value.shown(),
            allowed: allowed.into(),
        }
    }

    /// The same error with the key's leading `from` rewritten to `to` (unchanged when
    /// the key does not start with `from`).
    pub fn map_key(mut self, from: &str, to: &str) -> Self {
        if let Some(rest) = self.key.strip_prefix(from) {
            self.key = format!("{to}{rest}");
        }
        self
    }

    /// The same error with `prefix.` in front of its key.
    pub fn within(mut self, prefix: &str) -> Self {
        self.key = format!("{prefix}.{}", self.key);
        self
    }
}

/// How a value appears in an error message: numbers far from 1 in scientific notation
/// (`1e-6`, not `0.000001`), so the user recognises what they wrote.
pub trait Shown {
    /// The value as text.
    fn shown(&self) -> String;
}

impl Shown for f64 {
    fn shown(&self) -> String {
        shown(*self)
    }
}

impl Shown for &f64 {
    fn shown(&self) -> String {
        shown(**self)
    }
}

impl Shown for glam::DVec2 {
    fn shown(&self) -> String {
        format!("[{}, {}]", shown(self.x), shown(self.y))
    }
}

macro_rules! shown_by_display {
    ($($t:ty),*) => {$(
        impl Shown for $t {
            fn shown(&self) -> String {
                self.to_string()
            }
        }
    )*};
}
shown_by_display!(&str, String, &String, usize, &usize, u64, &u64, u32, &u32, u16, i64, i32);

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
pub fn positive(key: &str, v: f64) -> Result<(), InputError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(InputError::new(key, v, "must be a finite number > 0"))
    }
}

/// `Ok` when `v` is finite and not negative.
pub fn non_negative(key: &str, v: f64) -> Result<(), InputError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(InputError::new(key, v, "must be a finite number >= 0"))
    }
}

/// `Ok` when `lo <= v <= hi`.
pub fn in_range(key: &str, v: f64, lo: f64, hi: f64) -> Result<(), InputError> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(())
    } else {
        Err(InputError::new(
            key,
            v,
            format!("must be in [{}, {}]", shown(lo), shown(hi)),
        ))
    }
}

/// `Ok` when `name` can be one path component of an output (a run directory, a plot):
/// what a scenario names must stay inside the directory the user chose, so separators,
/// `.` and `..`, leading dots, control characters and the empty name are refused.
pub fn file_name(key: &str, name: &str) -> Result<(), InputError> {
    let bad = if name.trim().is_empty() {
        Some("must not be empty")
    } else if name.contains(['/', '\\']) {
        Some("must not contain '/' or '\\'")
    } else if name.starts_with('.') {
        Some("must not start with '.'")
    } else if name.chars().any(char::is_control) {
        Some("must not contain control characters")
    } else if name.contains(':') {
        Some("must not contain ':'")
    } else if name.len() > 200 {
        Some("must be at most 200 bytes long")
    } else {
        None
    };
    match bad {
        None => Ok(()),
        Some(why) => Err(InputError::new(
            key,
            format!("{name:?}"),
            format!(
                "{why}: it becomes a file or directory name (only --out chooses where outputs go)"
            ),
        )),
    }
}

/// `Ok` when the list `[[key]]` has at least one entry and no two share a name.
pub fn named_list<'a>(
    key: &str,
    names: impl ExactSizeIterator<Item = &'a str>,
) -> Result<(), InputError> {
    if names.len() == 0 {
        return Err(InputError::new(
            key,
            "(none)",
            format!("at least one [[{key}]] is required"),
        ));
    }
    let mut seen = std::collections::HashSet::new();
    for (k, n) in names.enumerate() {
        if !seen.insert(n) {
            return Err(InputError::new(
                format!("{key}[{k}].name"),
                format!("\"{n}\""),
                "names must be unique",
            ));
        }
    }
    Ok(())
}

/// The time step a scenario asks for: `dt` if given (refused above the stable limit
/// `critical`, whose meaning `why` states), else `safety` × the limit.
pub fn time_step(
    dt: Option<f64>,
    safety: f64,
    critical: f64,
    why: &str,
) -> Result<f64, InputError> {
    match dt {
        Some(dt) => {
            positive("run.dt", dt)?;
            if dt > critical {
                return Err(InputError::new(
                    "run.dt",
                    dt,
                    format!("above the stable limit {critical:.4e} s ({why})"),
                ));
            }
            Ok(dt)
        }
        None => Ok(safety * critical),
    }
}

/// Parses `text` (read from `origin`) as TOML into `T`; on failure one line naming the
/// file, the line and column, and what is wrong.
pub fn parse_toml<T: DeserializeOwned>(text: &str, origin: &str) -> Result<T, String> {
    toml::from_str::<T>(text).map_err(|e| toml_message(text, origin, &e))
}

/// The one-line form of a TOML error in `text`, read from `origin`.
pub fn toml_message(text: &str, origin: &str, e: &toml::de::Error) -> String {
    let at = e
        .span()
        .map(|s| {
            let before = &text[..s.start.min(text.len())];
            let line = before.matches('\n').count() + 1;
            let start = before.rfind('\n').map_or(0, |k| k + 1);
            let col = before.len() - start + 1;
            // The line itself names the key and the value the message is about.
            let text_line = text[start..].lines().next().unwrap_or("").trim();
            let shown: String = text_line.chars().take(80).collect();
            if shown.is_empty() {
                format!(" line {line}, column {col}:")
            } else {
                format!(" line {line}, column {col} ({shown}):")
            }
        })
        .unwrap_or_default();
    let msg = e.message().replace('\n', " ");
    format!("{origin}:{at} {}", msg.trim())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_as_written() {
        assert_eq!(shown(1e-6), "1e-6");
        assert_eq!(shown(0.25), "0.25");
        assert_eq!(shown(-3.5e9), "-3.5e9");
        assert_eq!(shown(f64::NAN), "NaN");
    }

    #[test]
    fn keys_map_into_the_users_file() {
        let e = InputError::new("particles[0].material", "\"x\"", "must be one of [\"q\"]");
        assert_eq!(
            e.map_key("particles[0]", "ring").to_string(),
            "ring.material = \"x\": must be one of [\"q\"]"
        );
        let e = InputError::new("youngs", -1.0, "must be a finite number > 0");
        assert_eq!(
            e.within("material.quartz").to_string(),
            "material.quartz.youngs = -1: must be a finite number > 0"
        );
    }

    #[test]
    fn toml_errors_name_line_and_column() {
        #[derive(serde::Deserialize, Debug)]
        #[serde(deny_unknown_fields)]
        #[allow(dead_code)]
        struct S {
            a: f64,
        }
        let e = parse_toml::<S>("a = 1.0\nb = 2\n", "s.toml").unwrap_err();
        assert!(e.starts_with("s.toml: line 2, column 1 (b = 2):"), "{e}");
        assert!(e.contains("unknown field"), "{e}");
        assert!(!e.contains('\n'));
    }
}
