//! The DEM front end: scenario type, validation, run loop and outputs.

pub mod assemble;
pub mod check;
pub mod checkpoint;
pub mod frames;
pub mod plots;
pub mod probes;
pub mod records;
pub mod run;
pub mod scenario;

use crate::fail;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// `grains run` for a DEM scenario: validate everything, then run and report.
pub fn cmd_run(
    text: &str,
    origin: &str,
    base: &Path,
    out: Option<PathBuf>,
    threads: usize,
    stop_at_step: Option<u64>,
) -> ExitCode {
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
    let opts = run::RunOptions {
        threads,
        stop_at_step,
        resume: None,
    };
    finish(run::run(&scn, text, asm, &out, opts), &out)
}

/// `grains resume DIR`: continue a DEM run from `DIR/checkpoint.bin`, with the scenario
/// copy the run wrote into `DIR`.
pub fn cmd_resume(dir: &Path, threads: usize, stop_at_step: Option<u64>) -> ExitCode {
    let scenario_path = dir.join("scenario.toml");
    let text = match std::fs::read_to_string(&scenario_path) {
        Ok(t) => t,
        Err(e) => {
            return fail(
                1,
                &format!(
                    "{}: cannot read: {e} (is {} a grains run directory?)",
                    scenario_path.display(),
                    dir.display()
                ),
            )
        }
    };
    let origin = scenario_path.display().to_string();
    let scn = match scenario::parse(&text, &origin) {
        Ok(v) => v,
        Err(e) => return fail(1, &e),
    };
    let (state, progress) = match checkpoint::load(&dir.join("checkpoint.bin"), &text, 1 << 31) {
        Ok(v) => v,
        Err(e) => return fail(1, &e),
    };
    let asm = match assemble::assemble_with(&scn, dir, Some(state.particles.clone())) {
        Ok(a) => a,
        Err(e) => return fail(1, &format!("{origin}: {e}")),
    };
    if state.contacts.n_walls != asm.setup.walls.len() {
        return fail(
            1,
            &format!(
                "{}: the checkpoint has {} walls, the scenario {}",
                origin,
                state.contacts.n_walls,
                asm.setup.walls.len()
            ),
        );
    }
    eprintln!(
        "grains: resuming {} at step {} of {} (t = {:.6e} s), {} threads → {}",
        scn.name,
        state.step,
        asm.steps,
        state.time,
        threads,
        dir.display()
    );
    let opts = run::RunOptions {
        threads,
        stop_at_step,
        resume: Some((state, progress)),
    };
    finish(run::run(&scn, &text, asm, dir, opts), dir)
}

fn finish(result: anyhow::Result<run::Outcome>, out: &Path) -> ExitCode {
    match result {
        Ok(o) => match o.status {
            run::Status::Unstable(m) => crate::report(&o.checks, Some(&m), out),
            run::Status::Paused => {
                eprintln!(
                    "grains: paused with a checkpoint; continue with `grains resume {}`",
                    out.display()
                );
                ExitCode::SUCCESS
            }
            run::Status::Interrupted => fail(
                130,
                &format!(
                    "interrupted; checkpoint written, continue with `grains resume {}`",
                    out.display()
                ),
            ),
            _ => crate::report(&o.checks, None, out),
        },
        Err(e) => fail(1, &format!("{e:#}")),
    }
}
