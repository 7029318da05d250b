//! `grains`: one scenario file in; ParaView frames, history, plots and a summary out.

mod analyze_cmd;
mod bench;
mod blast;
mod dem;
mod interrupt;
mod mpm;
mod pack_cmd;
mod progress;
mod summary;

use clap::{Parser, Subcommand};
use grains_core::checks::Check;
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
        /// Stop once this step is reached, with a checkpoint (`grains resume` goes on).
        #[arg(long)]
        stop_at_step: Option<u64>,
    },
    /// Continue a run from the checkpoint in its output directory.
    Resume {
        /// The run's output directory (holding scenario.toml and checkpoint.bin).
        dir: PathBuf,
        /// Worker threads (default: all cores); results do not depend on it.
        #[arg(long)]
        threads: Option<usize>,
        /// Stop again once this step is reached, with a checkpoint.
        #[arg(long)]
        stop_at_step: Option<u64>,
    },
    /// Validate a scenario without running it and print derived figures.
    Check {
        /// Scenario file (TOML).
        scenario: PathBuf,
        /// Print the figures as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Generate a dense packing from a spec (TOML); writes packing.txt, a frame, plots, summary.json.
    Pack {
        /// Packing spec (TOML).
        spec: PathBuf,
        /// Output directory (default: runs/<spec name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
    },
    /// Analyse a packing file (`x y r`) or a DEM frame (.vtp): psi6, contacts, fabric, sizes.
    Analyze {
        /// Packing file or VTP frame.
        file: PathBuf,
        /// Output directory (default: runs/analyze_<file stem>).
        #[arg(long)]
        out: Option<PathBuf>,
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

/// Which engine a scenario file is for: its top-level `engine` key.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Engine {
    Dem,
    Mpm,
    FemDem,
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
            stop_at_step,
        } => cmd_run(scenario.as_deref(), out, threads, stop_at_step),
        Command::Resume {
            dir,
            threads,
            stop_at_step,
        } => cmd_resume(&dir, threads, stop_at_step),
        Command::Check { scenario, json } => cmd_check(&scenario, json),
        Command::Bench { what } => bench::cmd_bench(what),
        Command::Pack { spec, out, threads } => pack_cmd::cmd_pack(&spec, out, threads),
        Command::Analyze { file, out, json } => analyze_cmd::cmd_analyze(&file, out, json),
    }
}

/// A scenario's text, where it came from, and the directory its relative paths start at.
struct Source {
    text: String,
    origin: String,
    base: PathBuf,
}

fn read_source(path: Option<&Path>) -> Result<Source, String> {
    match path {
        Some(p) => {
            let text = std::fs::read_to_string(p)
                .map_err(|e| format!("{}: cannot read scenario: {e}", p.display()))?;
            Ok(Source {
                text,
                origin: p.display().to_string(),
                base: p.parent().map(Path::to_path_buf).unwrap_or_default(),
            })
        }
        None => {
            eprintln!("grains: no scenario given, running the built-in demo (examples/dem/demo_hopper.toml)");
            Ok(Source {
                text: DEMO.to_string(),
                origin: "demo_hopper.toml".into(),
                base: PathBuf::from("."),
            })
        }
    }
}

/// Reads the `engine` key without interpreting the rest, so each engine can parse its own
/// scenario type strictly.
fn engine_of(src: &Source) -> Result<Engine, String> {
    let value: toml::Table = toml::from_str(&src.text).map_err(|e| {
        let line = e.span().map(|s| {
            src.text[..s.start.min(src.text.len())]
                .matches('\n')
                .count()
                + 1
        });
        let at = line.map(|l| format!(" line {l}:")).unwrap_or_default();
        format!(
            "{}:{at} not a valid TOML file: {}",
            src.origin,
            e.message().replace('\n', " ").trim()
        )
    })?;
    match value.get("engine") {
        None => Ok(Engine::Dem),
        Some(toml::Value::String(s)) if s == "dem" => Ok(Engine::Dem),
        Some(toml::Value::String(s)) if s == "mpm" => Ok(Engine::Mpm),
        Some(toml::Value::String(s)) if s == "fem_dem" => Ok(Engine::FemDem),
        Some(other) => Err(format!(
            "{}: engine = {other}: must be one of \"dem\", \"mpm\", \"fem_dem\"",
            src.origin
        )),
    }
}

fn cmd_resume(dir: &Path, threads: Option<usize>, stop_at_step: Option<u64>) -> ExitCode {
    let src = match read_source(Some(&dir.join("scenario.toml"))) {
        Ok(s) => s,
        Err(e) => return fail(1, &e),
    };
    let engine = match engine_of(&src) {
        Ok(e) => e,
        Err(e) => return fail(1, &e),
    };
    let threads = match set_threads(threads) {
        Ok(t) => t,
        Err(e) => return fail(1, &e),
    };
    interrupt::install();
    match engine {
        Engine::Dem => dem::cmd_resume(dir, threads, stop_at_step),
        other => fail(
            1,
            &format!(
                "{}: resume is supported for engine = \"dem\" runs, this one is {other:?}",
                dir.display()
            ),
        ),
    }
}

fn cmd_run(
    path: Option<&Path>,
    out: Option<PathBuf>,
    threads: Option<usize>,
    stop_at_step: Option<u64>,
) -> ExitCode {
    let src = match read_source(path) {
        Ok(s) => s,
        Err(e) => return fail(1, &e),
    };
    let engine = match engine_of(&src) {
        Ok(e) => e,
        Err(e) => return fail(1, &e),
    };
    let threads = match set_threads(threads) {
        Ok(t) => t,
        Err(e) => return fail(1, &e),
    };
    match engine {
        Engine::Dem => {
            interrupt::install();
            dem::cmd_run(
                &src.text,
                &src.origin,
                &src.base,
                out,
                threads,
                stop_at_step,
            )
        }
        Engine::Mpm => mpm::cmd_run(&src.text, &src.origin, &src.base, out, threads),
        Engine::FemDem => blast::cmd_run(&src.text, &src.origin, &src.base, out, threads),
    }
}

fn cmd_check(path: &Path, json: bool) -> ExitCode {
    let src = match read_source(Some(path)) {
        Ok(s) => s,
        Err(e) => return fail(1, &e),
    };
    match engine_of(&src) {
        Ok(Engine::Dem) => dem::check::cmd_check(&src.text, &src.origin, &src.base, json),
        Ok(Engine::Mpm) => mpm::cmd_check(&src.text, &src.origin, &src.base, json),
        Ok(Engine::FemDem) => blast::check::cmd_check(&src.text, &src.origin, &src.base, json),
        Err(e) => fail(1, &e),
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

/// Prints the checks and turns the end of a run into its exit code: 3 unstable,
/// 2 a check failed, 0 otherwise.
pub fn report(checks: &[Check], unstable: Option<&str>, out: &Path) -> ExitCode {
    for c in checks {
        eprintln!(
            "  check {:32} measured {:>12.6e}  expected {:>12.6e}  {}",
            c.name,
            c.measured,
            c.expected,
            if c.pass { "pass" } else { "FAIL" }
        );
    }
    if let Some(msg) = unstable {
        return fail(
            3,
            &format!(
                "run stopped, unstable at {msg}; last good output kept in {}",
                out.display()
            ),
        );
    }
    let failed = checks.iter().filter(|c| !c.pass).count();
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

/// Prints a one-line error and returns the exit code.
pub fn fail(code: u8, msg: &str) -> ExitCode {
    eprintln!("grains: error: {msg}");
    ExitCode::from(code)
}
