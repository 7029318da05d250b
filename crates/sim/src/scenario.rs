//! What kind of file a user gave: a DEM, MPM or FEM–DEM scenario (its `engine` key), or
//! a packing spec, which belongs to `grains pack`.

use crate::source::Source;
use crate::{blast, dem, mpm};
use grains_core::input::{parse_toml, toml_message};

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
