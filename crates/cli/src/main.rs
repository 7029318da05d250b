//! `grains`: one scenario file in; ParaView frames, history, plots and a summary out.

mod assemble;
mod bench;
mod check;
mod frames;
mod plots;
mod probes;
mod progress;
mod run;
mod scenario;
mod summary;

use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The built-in demo: disks pouring through a hopper onto a floor.
const DEMO: &str = include_str!("../../../examples/dem/demo_hopper.toml");

#[derive(Parser)]
#[command(
    name = "grains",
    version,
    about = "Simulation suite for granular materials under extreme loading"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scenario (no argument: the built-in demo).
    Run {
        /// Scenario file (TOML).
        scenario: Option<PathBuf>,
        /// Output directory (default: runs/<scenario name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
    },
    /// Validate a scenario without running it and print derived figures.
    Check {
        /// Scenario file (TOML).
        scenario: PathBuf,
        /// Print the figures as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Measure speed.
    Bench {
        #[command(subcommand)]
        what: bench::BenchCommand,
    },
}

/// Exit codes: 1 bad input (nothing written), 2 a check failed, 3 the run went unstable.
fn main() -> ExitCode {
    tracing_subscriber::fmt()
        .with_env_filter(tracing_subscriber::EnvFilter::from_default_env())
        .with_writer(std::io::stderr)
        .init();
    let cli = Cli::parse();
    match cli.command {
        Command::Run {
            scenario,
            out,
            threads,
        } => cmd_run(scenario.as_deref(), out, threads),
        Command::Check { scenario, json } => check::cmd_check(&scenario, json),
        Command::Bench { what } => bench::cmd_bench(what),
    }
}

/// Sets the worker count of the global pool; returns the count in use.
pub fn set_threads(threads: Option<usize>) -> Result<usize, String> {
    if let Some(t) = threads {
        if t == 0 {
            return Err("--threads = 0: must be at least 1".into());
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build_global()
            .map_err(|e| format!("cannot start {t} threads: {e}"))?;
    }
    Ok(rayon::current_num_threads())
}

fn cmd_run(path: Option<&Path>, out: Option<PathBuf>, threads: Option<usize>) -> ExitCode {
    let loaded = match path {
        Some(p) => scenario::load(p)
            .map(|(s, t)| (s, t, p.parent().map(Path::to_path_buf).unwrap_or_default())),
        None => {
            eprintln!("grains: no scenario given, running the built-in demo (examples/dem/demo_hopper.toml)");
            scenario::parse(DEMO, "demo_hopper.toml")
                .map(|s| (s, DEMO.to_string(), PathBuf::from(".")))
        }
    };
    let (scn, text, base) = match loaded {
        Ok(v) => v,
        Err(e) => return fail(1, &e),
    };
    let threads = match set_threads(threads) {
        Ok(t) => t,
        Err(e) => return fail(1, &e),
    };
    let asm = match assemble::assemble(&scn, &base) {
        Ok(a) => a,
        Err(e) => return fail(1, &format!("{}: {e}", origin(path))),
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
    match run::run(&scn, &text, asm, &out, threads) {
        Ok(outcome) => {
            for c in &outcome.checks {
                eprintln!(
                    "  check {:32} measured {:>12.6e}  expected {:>12.6e}  {}",
                    c.name,
                    c.measured,
                    c.expected,
                    if c.pass { "pass" } else { "FAIL" }
                );
            }
            if let run::Status::Unstable(msg) = &outcome.status {
                return fail(
                    3,
                    &format!(
                        "run stopped, unstable at {msg}; last good output kept in {}",
                        out.display()
                    ),
                );
            }
            let failed = outcome.checks.iter().filter(|c| !c.pass).count();
            if failed > 0 {
                return fail(
                    2,
                    &format!(
                        "{failed} check(s) failed; see {}",
                        out.join("summary.json").display()
                    ),
                );
            }
            eprintln!("grains: done; outputs in {}", out.display());
            ExitCode::SUCCESS
        }
        Err(e) => fail(1, &format!("{e:#}")),
    }
}

fn origin(path: Option<&Path>) -> String {
    path.map_or("demo_hopper.toml".into(), |p| p.display().to_string())
}

/// Prints a one-line error and returns the exit code.
pub fn fail(code: u8, msg: &str) -> ExitCode {
    eprintln!("grains: error: {msg}");
    ExitCode::from(code)
}
