//! What kind of file a user gave: a DEM, MPM or FEM–DEM scenario (its `engine` key), or
//! a packing spec, which belongs to `grains pack`.

use crate::source::Source;
use crate::{blast, dem, dem3d, mpm};
use grains_core::input::{file_name, parse_toml, toml_message, InputError};

/// A parsed scenario of any engine.
#[derive(Clone, Debug)]
pub enum Scenario {
    /// `engine = "dem"` (the default).
    Dem(dem::scenario::Scenario),
    /// `engine = "dem"` with `dim = 3`.
    Dem3(Box<dem3d::scenario::Scenario>),
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
            Scenario::Dem3(s) => &s.name,
            Scenario::Mpm(s) => &s.name,
            Scenario::FemDem(s) => &s.name,
        }
    }

    /// The engine's name.
    pub fn engine(&self) -> &'static str {
        match self {
            Scenario::Dem(_) | Scenario::Dem3(_) => "dem",
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

/// The keys of a DEM scenario that hold a point or a vector: as many numbers as the
/// scenario has dimensions (2D's `omega` is a number, not a list).
const VECTOR_KEYS: [&str; 14] = [
    "at", "velocity", "omega", "lo", "hi", "a", "b", "point", "normal", "axis", "centre", "base",
    "gravity", "periodic",
];

/// Refuses a vector of the other dimension anywhere in a DEM scenario, naming its key
/// (serde reads a table tagged by its `shape` or `source` without positions, and a
/// longer list into a shorter array without a word).
fn vector_lengths(table: &toml::Table, dim: usize, path: &str) -> Result<(), InputError> {
    for (key, value) in table {
        let here = if path.is_empty() {
            key.clone()
        } else {
            format!("{path}.{key}")
        };
        match value {
            toml::Value::Array(items) if VECTOR_KEYS.contains(&key.as_str()) => {
                let scalar =
                    |v: &toml::Value| !matches!(v, toml::Value::Table(_) | toml::Value::Array(_));
                if items.iter().all(scalar) && items.len() != dim {
                    let hint = if dim == 2 {
                        " (a 3D scenario sets dim = 3)"
                    } else {
                        ""
                    };
                    return Err(InputError::new(
                        here,
                        value.to_string(),
                        format!("must hold {dim} values, one per axis, in a {dim}D scenario{hint}"),
                    ));
                }
            }
            toml::Value::Array(items) => {
                for (k, item) in items.iter().enumerate() {
                    if let toml::Value::Table(t) = item {
                        vector_lengths(t, dim, &format!("{here}[{k}]"))?;
                    }
                }
            }
            toml::Value::Table(t) => vector_lengths(t, dim, &here)?,
            _ => {}
        }
    }
    Ok(())
}

fn by_engine(table: &toml::Table, text: &str, origin: &str) -> Result<Scenario, String> {
    let dem = table
        .get("engine")
        .is_none_or(|e| e.as_str() == Some("dem"));
    if dem {
        let three = table.get("dim") == Some(&toml::Value::Integer(3));
        vector_lengths(table, if three { 3 } else { 2 }, "")
            .map_err(|e| format!("{origin}: {e}"))?;
    }
    match table.get("dim") {
        None => {}
        Some(toml::Value::Integer(2)) if dem => {}
        Some(toml::Value::Integer(3)) if dem => {
            return Ok(Scenario::Dem3(Box::new(parse_toml(text, origin)?)));
        }
        Some(other) if dem => {
            return Err(format!("{origin}: dim = {other}: must be 2 or 3"));
        }
        Some(other) => {
            return Err(format!(
                "{origin}: dim = {other}: only engine = \"dem\" takes dim (the other engines are 2D)"
            ));
        }
    }
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
