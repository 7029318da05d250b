//! The MPM front end: scenario type, validation, run loop, outputs, and the benchmark.

pub mod assemble;
pub mod bench;
pub mod check;
pub mod frames;
pub mod plots;
pub mod probes;
pub mod run;
pub mod scenario;

use crate::fail;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Parses, validates (including any reference scenario a check names) and assembles.
fn prepare(
    text: &str,
    origin: &str,
    base: &Path,
) -> Result<(scenario::Scenario, assemble::Assembled), String> {
    let scn = scenario::parse(text, origin)?;
    let asm = assemble::assemble(&scn).map_err(|e| format!("{origin}: {e}"))?;
    for (k, c) in scn.checks.iter().enumerate() {
        if let scenario::CheckSpec::EnergyLossBelowReference {
            reference, body, ..
        } = c
        {
            let path = base.join(reference);
            let text = std::fs::read_to_string(&path).map_err(|e| {
                format!("{origin}: check[{k}].reference = \"{reference}\": cannot be read: {e}")
            })?;
            let r = scenario::parse(&text, &path.display().to_string())?;
            let ra = assemble::assemble(&r).map_err(|e| format!("{}: {e}", path.display()))?;
            if !ra.setup.bodies.iter().any(|b| &b.name == body) {
                return Err(format!(
                    "{origin}: check[{k}].body = \"{body}\": the reference has no such body"
                ));
            }
        }
    }
    Ok((scn, asm))
}

/// `grains run` for an MPM scenario: validate everything, then run and report.
pub fn cmd_run(
    text: &str,
    origin: &str,
    base: &Path,
    out: Option<PathBuf>,
    threads: usize,
) -> ExitCode {
    let (scn, asm) = match prepare(text, origin, base) {
        Ok(v) => v,
        Err(e) => return fail(1, &e),
    };
    let out = out.unwrap_or_else(|| PathBuf::from("runs").join(&scn.name));
    eprintln!(
        "grains: {} (mpm) — {} points in {} bodies, {}×{} cells, dt = {:.3e} s, {} steps, {} threads → {}",
        scn.name,
        asm.particles.len(),
        asm.setup.bodies.len(),
        asm.setup.grid.cells[0],
        asm.setup.grid.cells[1],
        asm.setup.dt,
        asm.steps,
        threads,
        out.display()
    );
    match run::run(&scn, text, base, asm, &out, threads) {
        Ok(o) => crate::report(&o.checks, o.unstable.as_deref(), &out),
        Err(e) => fail(1, &format!("{e:#}")),
    }
}

/// `grains check` for an MPM scenario.
pub fn cmd_check(text: &str, origin: &str, base: &Path, json: bool) -> ExitCode {
    match prepare(text, origin, base) {
        Ok((scn, asm)) => check::print(&scn, &asm, json),
        Err(e) => fail(1, &e),
    }
}
