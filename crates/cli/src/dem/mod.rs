//! The DEM front end: scenario type, validation, run loop and outputs.

pub mod assemble;
pub mod check;
pub mod frames;
pub mod plots;
pub mod probes;
pub mod run;
pub mod scenario;

use crate::fail;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// `grains run` for a DEM scenario: validate everything, then run and report.
pub fn cmd_run(text: &str, origin: &str, base: &Path, out: Option<PathBuf>, threads: usize) -> ExitCode {
    let scn = match scenario::parse(text, origin) {
        Ok(v) => v,
        Err(e) => return fail(1, &e),
    };
    let asm = match assemble::assemble(&scn, base) {
        Ok(a) => a,
        Err(e) => return fail(1, &format!("{origin}: {e}")),
    };
    let out = out.unwrap_or_else(|| PathBuf::from("runs").join(&scn.name));
    eprintln!(
        "grains: {} — {} particles, dt = {:.3e} s, {} steps, {} threads → {}",
        scn.name,
        asm.particles.len(),
        asm.setup.dt,
        asm.steps,
        threads,
        out.display()
    );
    match run::run(&scn, text, asm, &out, threads) {
        Ok(outcome) => crate::report(&outcome.checks, outcome.unstable.as_deref(), &out),
        Err(e) => fail(1, &format!("{e:#}")),
    }
}
