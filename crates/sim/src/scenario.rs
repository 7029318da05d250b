//! What kind of file a user gave: a DEM, MPM or FEM–DEM scenario (its `engine` key), or
//! a packing spec, which belongs to `grains pack`.

use crate::source::Source;
use crate::{blast, dem, mpm};
use grains_core::input::{file_name, parse_toml, toml_message, InputError};

/// A parsed scenario of any engine.
#[derive(Clone, Debug)]
pub enum Scenario {
    /// `engine = "dem"` (the default).
    Dem(dem::scenario::Scenario),
    /// `engine = "mpm"`.
    Mpm(mpm::scenario::Scenario),
    /// `engine = "fem_dem"`.
    FemDem(Box<blast::scenario::Scenario>),
}

impl Scenario {
    /// The scenario's name.
    pub fn name(&self) -> &str {
        match self {
            Scenario::Dem(s) => &s.name,
            Scenario::Mpm(s) => &s.name,
            Scenario::FemDem(s) => &s.name,
        }
    }

    /// The engine's name.
    pub fn engine(&self) -> &'static str {
        match self {
            Scenario::Dem(_) => "dem",
            Scenario::Mpm(_) => "mpm",
            Scenario::FemDem(_) => "fem_dem",
        }
    }
}

/// What a TOML file is, judged by its top-level keys.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    /// A scenario for `grains run`.
    Scenario,
    /// A packing spec for `grains pack` (it has `[sizes]` and no `engine`).
    PackingSpec,
}

/// Reads the top-level keys of `text` to tell a scenario from a packing spec.
pub fn kind_of(text: &str, origin: &str) -> Result<FileKind, String> {
    let table: toml::Table = toml::from_str(text).map_err(|e| {
        toml_message(text, origin, &e).replacen(": ", ": not a valid TOML file: ", 1)
    })?;
    Ok(
        if table.contains_key("sizes") && !table.contains_key("engine") {
            FileKind::PackingSpec
        } else {
            FileKind::Scenario
        },
    )
}

/// Parses a scenario strictly (`deny_unknown_fields` everywhere), by its `engine` key.
pub fn parse(src: &Source) -> Result<Scenario, String> {
    let (text, origin) = (src.text.as_str(), src.origin.as_str());
    if kind_of(text, origin)? == FileKind::PackingSpec {
        return Err(format!(
            "{origin}: this is a packing spec (it has [sizes]); make the packing with `grains pack {origin}`"
        ));
    }
    let table: toml::Table = toml::from_str(text).map_err(|e| toml_message(text, origin, &e))?;
    let scenario = by_engine(&table, text, origin)?;
    output_names(&scenario).map_err(|e| format!("{origin}: {e}"))?;
    step_given_once(&table).map_err(|e| format!("{origin}: {e}"))?;
    Ok(scenario)
}

/// `run.dt` is used as given and `run.safety` only sets the default step: both given
/// would leave one silently ignored.
fn step_given_once(table: &toml::Table) -> Result<(), InputError> {
    let run = table.get("run").and_then(toml::Value::as_table);
    if let Some(run) = run {
        if let (Some(dt), Some(safety)) = (run.get("dt"), run.get("safety")) {
            return Err(InputError::new(
                "run.safety",
                safety.to_string(),
                format!("cannot be given with run.dt = {dt}: dt is used as given and safety only sets the default step; keep one"),
            ));
        }
    }
    Ok(())
}

/// Every name a scenario gives that becomes part of an output path: the run's (its
/// default directory), and an MPM run's bodies and checks (plot files).
fn output_names(s: &Scenario) -> Result<(), InputError> {
    file_name("name", s.name())?;
    if let Scenario::Mpm(m) = s {
        for (i, b) in m.bodies.iter().enumerate() {
            file_name(&format!("body[{i}].name"), &b.name)?;
        }
        for (i, c) in m.checks.iter().enumerate() {
            file_name(&format!("check[{i}].name"), c.name())?;
        }
    }
    Ok(())
}

fn by_engine(table: &toml::Table, text: &str, origin: &str) -> Result<Scenario, String> {
    match table.get("engine") {
        None => Ok(Scenario::Dem(parse_toml(text, origin)?)),
        Some(toml::Value::String(s)) if s == "dem" => Ok(Scenario::Dem(parse_toml(text, origin)?)),
        Some(toml::Value::String(s)) if s == "mpm" => Ok(Scenario::Mpm(parse_toml(text, origin)?)),
        Some(toml::Value::String(s)) if s == "fem_dem" => {
            Ok(Scenario::FemDem(Box::new(parse_toml(text, origin)?)))
        }
        Some(other) => Err(format!(
            "{origin}: engine = {other}: must be one of \"dem\", \"mpm\", \"fem_dem\""
        )),
    }
}
