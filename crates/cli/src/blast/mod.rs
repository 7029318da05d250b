//! The explosive-dispersal front end (`engine = "fem_dem"`): a charge modelled by
//! grains-fem, a particle ring by grains-dem, coupled here through contact at the
//! charge's edge (xue-2019 App. C). A scenario without a ring is a bare charge.

pub mod analysis;
pub mod assemble;
pub mod check;
pub mod coupling;
pub mod frames;
pub mod plots;
pub mod probes;
pub mod ring;
pub mod run;
pub mod scenario;
pub mod step;

use crate::fail;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// `grains run` for a blast scenario: validate everything, then run and report.
pub fn cmd_run(
    text: &str,
    origin: &str,
    base: &Path,
    out: Option<PathBuf>,
    threads: usize,
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
    let d = check::derived(&scn, &asm);
    eprintln!(
        "grains: {} — charge {} ({} elements), {} particles, F/B = {}, dt ≈ {:.3e} s, {} threads → {}",
        scn.name,
        asm.fem.explosive.name,
        asm.mesh.tris.len(),
        d["particles"],
        d.get("fill_to_burster_ratio").map_or("-".to_string(), |v| format!("{:.3}", v.as_f64().unwrap_or(f64::NAN))),
        d["dt_initial"].as_f64().unwrap_or(f64::NAN),
        threads,
        out.display()
    );
    match run::run(&scn, text, asm, &out, threads) {
        Ok(o) => crate::report(&o.checks, o.unstable.as_deref(), &out),
        Err(e) => fail(1, &format!("{e:#}")),
    }
}
