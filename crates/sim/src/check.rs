//! `grains check`: what a run would do, without running it — for people as aligned
//! lines, for programs as JSON with the same keys.

use crate::estimate::{self, Estimate};
use crate::scenario::{self, Scenario};
use crate::source::Source;
use crate::{blast, dem, mpm};
use grains_core::checks::Check;
use serde_json::{Map, Value};

/// One derived figure.
#[derive(Clone, Debug)]
pub struct Line {
    /// JSON key.
    pub key: &'static str,
    /// JSON value (SI).
    pub value: Value,
    /// How a person reads it; `None` for JSON only.
    pub text: Option<String>,
}

impl Line {
    /// A figure with its text.
    pub fn new(key: &'static str, value: impl Into<Value>, text: impl Into<String>) -> Self {
        Line {
            key,
            value: value.into(),
            text: Some(text.into()),
        }
    }

    /// A figure for JSON only.
    pub fn quiet(key: &'static str, value: impl Into<Value>) -> Self {
        Line {
            key,
            value: value.into(),
            text: None,
        }
    }
}

/// Everything `grains check` reports.
#[derive(Clone, Debug, Default)]
pub struct Derived {
    /// Figures, in print order.
    pub lines: Vec<Line>,
    /// Checks that can be judged without running (e.g. a ring's F/B).
    pub checks: Vec<Check>,
    /// Things the user should know before starting.
    pub warnings: Vec<String>,
}

impl Derived {
    /// The figures as one JSON object (with `checks` and `warnings`).
    pub fn json(&self) -> Value {
        let mut m = Map::new();
        for l in &self.lines {
            m.insert(l.key.into(), l.value.clone());
        }
        m.insert("checks".into(), serde_json::json!(self.checks));
        m.insert("warnings".into(), serde_json::json!(self.warnings));
        Value::Object(m)
    }

    /// The figures as aligned lines.
    pub fn text(&self) -> String {
        let shown: Vec<(String, &String)> = self
            .lines
            .iter()
            .filter_map(|l| Some((label(l.key), l.text.as_ref()?)))
            .collect();
        let width = shown
            .iter()
            .map(|(k, _)| k.chars().count())
            .max()
            .unwrap_or(0)
            + 2;
        let mut s = String::new();
        for (k, t) in shown {
            s.push_str(&format!("{k:width$}{t}\n"));
        }
        for c in &self.checks {
            s.push_str(&format!(
                "{:width$}{} measured {:.4} expected {:.4} ± {:.0} %: {}\n",
                "check",
                c.name,
                c.measured,
                c.expected,
                100.0 * c.tolerance,
                if c.pass { "pass" } else { "FAIL" }
            ));
        }
        for w in &self.warnings {
            s.push_str(&format!("{:width$}{w}\n", "warning"));
        }
        s
    }

    /// The shared head: name, engine, description.
    pub fn head(name: &str, engine: &str, description: &str) -> Vec<Line> {
        let mut v = vec![
            Line::new("scenario", name, name),
            Line::new("engine", engine, engine),
        ];
        if !description.trim().is_empty() {
            v.push(Line::new(
                "description",
                description.trim(),
                description.trim(),
            ));
        }
        v
    }

    /// The lines of a run in fixed steps: the step against its stable limit, the
    /// duration and the step count.
    pub fn fixed_step(dt: f64, dt_critical: f64, duration: f64, steps: u64) -> [Line; 4] {
        [
            Line::new(
                "dt",
                dt,
                format!(
                    "{dt:.4e} s ({:.3} of the stable limit {dt_critical:.4e} s)",
                    dt / dt_critical
                ),
            ),
            Line::quiet("dt_critical", dt_critical),
            Line::new("duration", duration, format!("{duration:.4e} s")),
            Line::new(
                "steps",
                steps,
                format!("{steps} (exact: the step is fixed)"),
            ),
        ]
    }

    /// The shared tail: the estimate.
    pub fn cost(&mut self, e: &Estimate) {
        self.lines.push(Line::new(
            "memory_bytes_estimate",
            e.memory_bytes,
            format!("≈ {}", estimate::bytes(e.memory_bytes)),
        ));
        self.lines.push(Line::new(
            "wall_time_estimate_s",
            e.wall_time_s,
            format!(
                "≈ {} on {} threads (from the speeds in BENCHMARKS.md; within a factor 2)",
                estimate::duration(e.wall_time_s),
                e.threads
            ),
        ));
        self.warnings.extend(e.warning());
    }
}

/// How a figure's key reads in the text form.
fn label(key: &str) -> String {
    match key {
        "memory_bytes_estimate" => "memory".into(),
        "wall_time_estimate_s" => "wall time".into(),
        "fill_to_burster_ratio" => "F/B".into(),
        "dt" | "dt_initial" => "time step".into(),
        "steps_estimate" => "steps (typical)".into(),
        "checkpoint_bytes" => "checkpoints".into(),
        k => k.replace('_', " "),
    }
}

/// Validates `src` and derives its figures; `threads` is what the run would use.
pub fn check(src: &Source, threads: usize) -> Result<Derived, String> {
    match scenario::parse(src)? {
        Scenario::Dem(s) => dem::check::derived(&s, src, threads),
        Scenario::Dem3(s) => crate::dem3d::run::derived(&s, src, threads),
        Scenario::Mpm(s) => mpm::check::derived(&s, src, threads),
        Scenario::FemDem(s) => blast::check::derived(&s, src, threads),
    }
}
