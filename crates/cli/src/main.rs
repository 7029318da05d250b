//! `grains`: one scenario file in; ParaView frames, history, plots and a summary out.
//! Everything it does is grains-sim's; this is the command line: arguments, progress,
//! messages and exit codes.

mod interrupt;
mod memory;
mod progress;
mod ranks;

use clap::{Parser, Subcommand};
use grains_sim::run::{self as sim_run, Finished, RunError, RunOptions};
use grains_sim::{bench, check, driver, Source, Status};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

const EXIT_CODES: &str = "Exit codes:
  0    success (or paused at --stop-at-step with a checkpoint)
  1    bad input (one line names the key, the value and what is allowed; nothing is
       written), a mistyped command line, or an output directory that cannot be
       written (refused before anything is computed)
  2    a validation check failed (see summary.json)
  3    the run went unstable (NaN, runaway overlap, a particle through the charge's
       edge, CFL breach, a collapsed time step, a DEM particle leaving the domain or
       moving more than its radius in a step); the output written before that point
       is kept and its checks fail
  130  interrupted by Ctrl-C or SIGTERM (DEM and FEM–DEM runs write a checkpoint first)";

#[derive(Parser)]
#[command(
    name = "grains",
    version,
    about = "Simulation suite for granular materials under extreme loading",
    after_help = EXIT_CODES
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scenario (no argument: the built-in demo).
    #[command(after_help = EXIT_CODES)]
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
    /// Continue a DEM or FEM–DEM run from the checkpoint in its output directory.
    #[command(after_help = EXIT_CODES)]
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
    /// Validate a scenario without running it and print derived figures: particles,
    /// time step, steps, memory and wall-time estimates.
    Check {
        /// Scenario file (TOML).
        scenario: PathBuf,
        /// Print the figures as JSON.
        #[arg(long)]
        json: bool,
        /// Threads the wall-time estimate is for (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// DEM (2D, 3D) and FEM–DEM rings: also spread the start over this many ranks as
        /// `mpirun -np N grains run` would, and print each rank's particles, ghosts and
        /// memory (a ring's charge on every rank).
        #[arg(long)]
        ranks: Option<usize>,
    },
    /// Generate a dense packing from a spec (TOML); writes packing.txt, a frame, plots,
    /// summary.json.
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
    /// Analyse a packing file (`x y r`) or a DEM frame (.vtp): psi6, contacts, fabric,
    /// sizes. Given a run directory of a ring (FEM–DEM, or DEM with [dispersal]): the
    /// dispersal analysis of its frames (fields, fronts, band/spall, shear bands, jets,
    /// the ring models).
    Analyze {
        /// Packing file, VTP frame, or run directory.
        file: PathBuf,
        /// Output directory (default: runs/analyze_<file stem>; RUN_DIR/analysis for a
        /// run directory).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Print the figures as JSON.
        #[arg(long)]
        json: bool,
        /// Run directory only: draw the polar maps at the frames nearest these times
        /// (s) (default: the scenario's `[analysis.dispersal] times`, or the last
        /// frame). Every frame is analysed either way.
        #[arg(long, value_delimiter = ',', num_args = 1..)]
        times: Option<Vec<f64>>,
    },
    /// Measure speed; prints `particle-steps/s: X` last.
    Bench {
        #[command(subcommand)]
        what: BenchCommand,
    },
}

#[derive(Subcommand)]
enum BenchCommand {
    /// The DEM engine on a bed of disks with the peer benchmark's physics (LAMMPS
    /// gran/hooke/history), or (--dim 3) on a bed of spheres with the 3D deck's
    /// (pair_style granular: hertz/material, tsuji, mindlin).
    Dem {
        /// Dimension: 2 (disks) or 3 (spheres; needs --lammps-data).
        #[arg(long, default_value_t = 2)]
        dim: usize,
        /// Number of disks in a bed grains builds itself (ignored with --lammps-data).
        #[arg(long, default_value_t = 20_000)]
        particles: usize,
        /// Start from this LAMMPS data file (atom_style sphere), as the peer benchmark
        /// does.
        #[arg(long)]
        lammps_data: Option<PathBuf>,
        /// Repeat the data file's bed this many times side by side along x (18 × the
        /// 100 k bed is 1.8 M disks).
        #[arg(long, default_value_t = 1)]
        tile: usize,
        /// Timed steps.
        #[arg(long, default_value_t = 2000)]
        steps: u64,
        /// Worker threads.
        #[arg(long)]
        threads: Option<usize>,
    },
    /// The MPM engine: a block (or two in contact) falling in a walled box.
    Mpm {
        /// Material points.
        #[arg(long, default_value_t = 32_768)]
        particles: usize,
        /// Cells per side of the unit box.
        #[arg(long, default_value_t = 128)]
        grid: usize,
        /// Timed steps.
        #[arg(long, default_value_t = 2000)]
        steps: u64,
        /// Worker threads.
        #[arg(long)]
        threads: Option<usize>,
        /// 1: one block; 2: two stacked blocks in frictional contact.
        #[arg(long, default_value_t = 1)]
        bodies: usize,
        /// Shape function: linear, gimp or bspline2 (default: the peer's quadratic
        /// B-spline).
        #[arg(long, default_value = "bspline2")]
        shape: String,
        /// Stress update: usf, usl, usavg or musl (default: USL, two passes like the
        /// peer).
        #[arg(long, default_value = "usl")]
        update: String,
        /// The block's material: elastic, thermal, neo_hookean, j2, maxwell (2 Prony
        /// terms), maxwell3 or maxwell4; all with K = 200, instantaneous G = 100.
        #[arg(long, default_value = "elastic")]
        material: String,
    },
}

fn main() -> ExitCode {
    memory::return_large_blocks();
    // Started by mpirun on several ranks: each rank says why it cannot go on, before
    // anything is read or written (not N runs writing into one directory).
    let launch = grains_mpi::launch();
    if let Some(line) = grains_mpi::refuse(launch) {
        eprintln!("error: {line}");
        return ExitCode::from(1);
    }
    tracing_subscriber::fmt()
        .with_env_filter(tracing_subscriber::EnvFilter::from_default_env())
        .with_writer(std::io::stderr)
        .init();
    let cli = match Cli::try_parse_from(negative_times(std::env::args_os())) {
        Ok(cli) => cli,
        Err(e) => return argument_error(e),
    };
    // Only rank 0 speaks; every rank exits with the same code.
    let quiet = launch.rank != 0;
    if let Some(line) = ranks::refuse(launch, &name_of(&cli.command)) {
        return if quiet {
            ExitCode::from(1)
        } else {
            fail(1, &line)
        };
    }
    let result = match cli.command {
        Command::Run {
            scenario,
            out,
            threads,
            stop_at_step,
        } if launch.ranks > 1 => {
            ranks::cmd_run(launch, scenario.as_deref(), out, threads, stop_at_step)
        }
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
        } if launch.ranks > 1 => ranks::cmd_resume(launch, &dir, threads, stop_at_step),
        Command::Resume {
            dir,
            threads,
            stop_at_step,
        } => cmd_resume(&dir, threads, stop_at_step),
        Command::Check {
            scenario,
            json,
            threads,
            ranks,
        } => cmd_check(&scenario, json, threads, ranks),
        Command::Pack { spec, out, threads } => cmd_pack(&spec, out, threads),
        Command::Analyze {
            file,
            out,
            json,
            times,
        } => cmd_analyze(&file, out, json, times.as_deref()),
        Command::Bench { what } => cmd_bench(what, launch.ranks > 1),
    };
    result.unwrap_or_else(|(code, msg)| {
        if quiet {
            ExitCode::from(code)
        } else {
            fail(code, &msg)
        }
    })
}

/// The command as typed, for the refusal of one that does not run on several ranks.
fn name_of(c: &Command) -> String {
    match c {
        Command::Run { .. } => "run".into(),
        Command::Resume { .. } => "resume".into(),
        Command::Check { .. } => "check".into(),
        Command::Pack { .. } => "pack".into(),
        Command::Analyze { .. } => "analyze".into(),
        Command::Bench {
            what: BenchCommand::Dem { dim: 2, .. },
        } => "bench dem".into(),
        Command::Bench {
            what: BenchCommand::Dem { dim, .. },
        } => format!("bench dem --dim {dim}"),
        Command::Bench {
            what: BenchCommand::Mpm { .. },
        } => "bench mpm".into(),
    }
}

/// An error to report: exit code and one line.
type Failure = (u8, String);

fn input(msg: impl std::fmt::Display) -> Failure {
    (1, msg.to_string())
}

/// Sets the worker count of the global pool; returns the count in use.
fn set_threads(threads: Option<usize>) -> Result<usize, Failure> {
    if let Some(t) = threads {
        if t == 0 {
            return Err(input("--threads = 0: must be at least 1"));
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build_global()
            .map_err(|e| input(format!("cannot start {t} threads: {e}")))?;
    }
    Ok(rayon::current_num_threads())
}

fn options(out: PathBuf, threads: usize, stop_at_step: Option<u64>) -> RunOptions<'static> {
    RunOptions {
        out,
        threads,
        stop_at_step,
        interrupt: Some(interrupt::install(true)),
        progress: Box::new(progress::Bar::new()),
    }
}

fn cmd_run(
    path: Option<&Path>,
    out: Option<PathBuf>,
    threads: Option<usize>,
    stop_at_step: Option<u64>,
) -> Result<ExitCode, Failure> {
    let src = match path {
        Some(p) => Source::read(p).map_err(input)?,
        None => {
            eprintln!("grains: no scenario given, running the built-in demo (examples/dem/demo_hopper.toml)");
            Source::demo()
        }
    };
    let threads = set_threads(threads)?;
    let scn = grains_sim::scenario::parse(&src).map_err(input)?;
    let out = out.unwrap_or_else(|| driver::default_out(scn.name()));
    driver::writable_out(&out).map_err(input)?;
    report(
        sim_run::run(&src, options(out, threads, stop_at_step)),
        true,
    )
}

fn cmd_resume(
    dir: &Path,
    threads: Option<usize>,
    stop_at_step: Option<u64>,
) -> Result<ExitCode, Failure> {
    let threads = set_threads(threads)?;
    report(
        sim_run::resume(dir, options(dir.to_path_buf(), threads, stop_at_step)),
        true,
    )
}

/// Prints the checks (when `speak`: rank 0 of several prints for all) and turns the end
/// of a run into its exit code.
fn report(result: Result<Finished, RunError>, speak: bool) -> Result<ExitCode, Failure> {
    let done = result.map_err(input)?;
    for c in done.checks.iter().filter(|_| speak) {
        eprintln!(
            "  check {:32} measured {:>12.6e}  expected {:>12.6e}  {}",
            c.name,
            c.measured,
            c.expected,
            if c.pass { "pass" } else { "FAIL" }
        );
    }
    let out = done.out.display();
    match &done.status {
        Status::Unstable(m) => Err((
            3,
            format!("run stopped, unstable at {m}; last good output kept in {out}"),
        )),
        Status::Interrupted => Err((
            130,
            format!(
                "interrupted; continue with `grains resume {out}` where a checkpoint was written"
            ),
        )),
        Status::Paused => {
            if speak {
                eprintln!("grains: paused with a checkpoint; continue with `grains resume {out}`");
            }
            Ok(ExitCode::SUCCESS)
        }
        Status::Completed | Status::AtRest => {
            let failed = done.checks.iter().filter(|c| !c.pass).count();
            if failed > 0 {
                return Err((
                    2,
                    format!("{failed} check(s) failed; see {out}/summary.json"),
                ));
            }
            if speak {
                eprintln!("grains: done ({}); outputs in {out}", done.status.name());
            }
            Ok(ExitCode::SUCCESS)
        }
    }
}

fn cmd_check(
    path: &Path,
    json: bool,
    threads: Option<usize>,
    ranks: Option<usize>,
) -> Result<ExitCode, Failure> {
    let src = Source::read(path).map_err(input)?;
    if threads == Some(0) {
        return Err(input("--threads = 0: must be at least 1"));
    }
    let threads = threads.unwrap_or_else(rayon::current_num_threads);
    let d = check::check(&src, threads).map_err(input)?;
    let spread = ranks
        .map(|n| grains_sim::ranks::spread::spread(&src, n))
        .transpose()
        .map_err(input)?;
    if json {
        let mut v = d.json();
        if let Some(s) = &spread {
            v["ranks"] = s.json();
        }
        let text = serde_json::to_string_pretty(&v).map_err(input)?;
        println!("{text}");
    } else {
        print!("{}", d.text());
        if let Some(s) = &spread {
            print!("{}", s.text());
        }
        println!("ok");
    }
    Ok(if d.checks.iter().all(|c| c.pass) {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(2)
    })
}

fn cmd_pack(
    spec: &Path,
    out: Option<PathBuf>,
    threads: Option<usize>,
) -> Result<ExitCode, Failure> {
    if let Some(p) = grains_sim::pack3d::prepare(spec).map_err(input)? {
        let threads = set_threads(threads)?;
        let out = out.unwrap_or_else(|| driver::default_out(&p.spec.name));
        driver::writable_out(&out).map_err(input)?;
        eprintln!(
            "grains: pack {} — {} spheres jammed, {threads} threads → {}",
            p.spec.name,
            p.spec.sizes.count,
            out.display()
        );
        let done = grains_sim::pack3d::pack(&p, &out).map_err(|e| input(format!("{e:#}")))?;
        return packed(&done, &out);
    }
    let (s, text, v) = grains_sim::pack::prepare(spec).map_err(input)?;
    let threads = set_threads(threads)?;
    let out = out.unwrap_or_else(|| driver::default_out(&s.name));
    driver::writable_out(&out).map_err(input)?;
    eprintln!(
        "grains: pack {} — about {:.0} disks of d0 = {:.4e} m, {threads} threads → {}",
        s.name,
        v.estimated_particles,
        v.d0,
        out.display()
    );
    let mut watch = PackWatch {
        bar: progress::Bar::new(),
        what: format!("packing {}", s.name),
    };
    let done = grains_sim::pack::pack(&s, &text, &v, &out, &mut watch)
        .map_err(|e| input(format!("{e:#}")))?;
    grains_sim::driver::Progress::finish(&mut watch.bar);
    packed(&done, &out)
}

/// Prints a packing's figures and checks; exit 2 when a check failed.
fn packed(done: &grains_sim::pack::Packed, out: &Path) -> Result<ExitCode, Failure> {
    print!("{}", grains_sim::analyze::main_figures(&done.summary));
    let failed = done.checks.iter().filter(|c| !c.pass).count();
    for c in &done.checks {
        eprintln!(
            "  check {:32} measured {:>12.6e}  limit {:>12.6e}  {}",
            c.name,
            c.measured,
            c.expected,
            if c.pass { "pass" } else { "FAIL" }
        );
    }
    if failed > 0 {
        return Err((
            2,
            format!(
                "{failed} check(s) failed; see {}/summary.json",
                out.display()
            ),
        ));
    }
    eprintln!("grains: done; outputs in {}", out.display());
    Ok(ExitCode::SUCCESS)
}

/// `grains pack`'s display: the protocol's stage lines above a progress bar.
struct PackWatch {
    bar: progress::Bar,
    what: String,
}

impl grains_sim::pack::Watch for PackWatch {
    fn line(&mut self, line: String) {
        self.bar.println(&format!("  {line}"));
    }

    fn progress(&mut self, done: f64) {
        use grains_sim::driver::Progress;
        self.bar.stage(&self.what, done);
    }
}

fn cmd_analyze(
    file: &Path,
    out: Option<PathBuf>,
    json: bool,
    times: Option<&[f64]>,
) -> Result<ExitCode, Failure> {
    use grains_sim::dispersal::run_dir;
    if run_dir::is_run_dir(file) {
        let out = out.unwrap_or_else(|| file.join("analysis"));
        driver::writable_out(&out).map_err(input)?;
        let figures = run_dir::analyze_run(file, &out, times).map_err(input)?;
        if json {
            let v = serde_json::Value::Object(figures);
            println!("{}", serde_json::to_string_pretty(&v).map_err(input)?);
        } else {
            print!("{}", run_dir::main_figures(&figures));
            eprintln!(
                "grains: dispersal analysis of {} written to {}",
                file.display(),
                out.display()
            );
        }
        return Ok(ExitCode::SUCCESS);
    }
    if times.is_some() {
        return Err(input(format!(
            "--times: only for a run directory, and {} is a file",
            file.display()
        )));
    }
    let stem = file
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_else(|| "sample".into());
    let out = out.unwrap_or_else(|| driver::default_out(&format!("analyze_{stem}")));
    driver::writable_out(&out).map_err(input)?;
    let figures = grains_sim::analyze::analyze(file, &out).map_err(input)?;
    if json {
        let v = serde_json::Value::Object(figures);
        println!("{}", serde_json::to_string_pretty(&v).map_err(input)?);
    } else {
        print!("{}", grains_sim::analyze::main_figures(&figures));
        eprintln!(
            "grains: analysis of {} written to {}",
            file.display(),
            out.display()
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn cmd_bench(what: BenchCommand, several: bool) -> Result<ExitCode, Failure> {
    let r = match what {
        BenchCommand::Dem {
            dim,
            particles,
            lammps_data,
            tile,
            steps,
            threads,
        } => {
            set_threads(threads)?;
            if tile == 0 {
                return Err(input("--tile = 0: must be at least 1"));
            }
            match (dim, lammps_data) {
                (2, data) => {
                    let bed = match data {
                        Some(path) => bench::dem::Bed::LammpsData(path, tile),
                        None => bench::dem::Bed::Built(particles),
                    };
                    if several {
                        return ranks::cmd_bench_dem(bed, steps);
                    }
                    bench::dem::run(&bed, steps)
                }
                (3, Some(path)) if tile == 1 => bench::dem3d::run(&path, steps),
                (3, Some(_)) => Err(format!(
                    "--tile = {tile}: a 3D bed is not tiled (only 1); build a larger one with LAMMPS (bench/in.replicate3d.lmp)"
                )),
                (3, None) => Err(
                    "--dim = 3 without --lammps-data: the 3D bench runs on a bed of spheres from a LAMMPS data file".into(),
                ),
                _ => Err(format!("--dim = {dim}: must be 2 or 3")),
            }
        }
        BenchCommand::Mpm {
            particles,
            grid,
            steps,
            threads,
            bodies,
            shape,
            update,
            material,
        } => {
            set_threads(threads)?;
            bench::mpm::run(&bench::mpm::Options {
                particles,
                grid,
                steps,
                bodies,
                shape,
                update,
                material,
            })
        }
    }
    .map_err(input)?;
    print!("{}", r.text());
    Ok(ExitCode::SUCCESS)
}

/// `--times -1e-6` as `--times=-1e-6`: clap takes a value starting with '-' after a
/// flag for another flag (here `-1`), so a negative time would be refused as an unknown
/// argument rather than as a time outside the run.
fn negative_times(args: impl Iterator<Item = std::ffi::OsString>) -> Vec<std::ffi::OsString> {
    let mut out: Vec<std::ffi::OsString> = Vec::new();
    for a in args {
        let numbers = a.to_str().is_some_and(|s| {
            s.starts_with('-') && s.split(',').all(|t| t.trim().parse::<f64>().is_ok())
        });
        if numbers && out.last().is_some_and(|l| l == "--times") {
            let flag = out.pop().unwrap_or_default();
            let mut joined = flag;
            joined.push("=");
            joined.push(&a);
            out.push(joined);
        } else {
            out.push(a);
        }
    }
    out
}

/// clap's refusal as one line and exit code 1 (bad input), as for every other bad
/// input; `--help` and `--version` print in full and succeed.
fn argument_error(e: clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    match e.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
            let _ = e.print();
            ExitCode::SUCCESS
        }
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            let given: Vec<String> = std::env::args().skip(1).collect();
            let cmd = ["grains".to_string()]
                .into_iter()
                .chain(given)
                .collect::<Vec<_>>()
                .join(" ");
            fail(
                1,
                &format!("`{cmd}` needs a subcommand (see `{cmd} --help`)"),
            )
        }
        _ => {
            let text = e.render().to_string();
            let first = text
                .lines()
                .find(|l| !l.trim().is_empty())
                .unwrap_or("bad arguments");
            let first = first.trim_start_matches("error: ");
            fail(1, &format!("{first} (see `grains --help`)"))
        }
    }
}

/// Prints a one-line error and returns the exit code.
fn fail(code: u8, msg: &str) -> ExitCode {
    eprintln!("grains: error: {msg}");
    ExitCode::from(code)
}
