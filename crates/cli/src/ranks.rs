//! The commands that run on several ranks (`mpirun -np N grains ...`, in a build with
//! the `mpi` feature): `run` and `resume` of a DEM scenario (2D or 3D) and `bench dem`. Rank 0 prints and
//! writes; every rank exits with the same code. Other commands are refused on every
//! rank before anything is read.

use super::{input, progress, report, set_threads, Failure};
use grains_mpi::Launch;
use grains_sim::dem::ranks::Link;
use grains_sim::run::{self as sim_run, RunOptions};
use grains_sim::{bench, driver, Source};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Why `command` (its name as typed) cannot run on the ranks of `launch`, as one line.
pub fn refuse(launch: Launch, command: &str) -> Option<String> {
    (launch.ranks > 1 && !matches!(command, "run" | "resume" | "bench dem")).then(|| {
        format!(
            "`grains {command}` does not run on several ranks yet (ranks = {}; docs/parallel.md); allowed under mpirun: `grains run` and `grains resume` (DEM, 2D and 3D) and `grains bench dem`, or 1 rank",
            launch.ranks
        )
    })
}

/// MPI, finalised when dropped.
type Mpi = Box<dyn std::any::Any>;

/// The MPI world as the transport of a run, and MPI itself, finalised when the second
/// is dropped (after rank 0 has said how the run ended: [`ended`]).
fn world() -> Result<(Link, Mpi), Failure> {
    #[cfg(feature = "mpi")]
    {
        grains_mpi::World::init_apart()
            .map(|(w, mpi)| (Link(Box::new(w)), Box::new(mpi) as Mpi))
            .ok_or_else(|| {
                input("MPI cannot be initialised for this run: it was already, or the library does not offer MPI_THREAD_SERIALIZED")
            })
    }
    #[cfg(not(feature = "mpi"))]
    {
        Err(input("this grains was built without MPI"))
    }
}

/// `grains run SCENARIO` on every rank of `launch`.
pub fn cmd_run(
    launch: Launch,
    path: Option<&Path>,
    out: Option<PathBuf>,
    threads: Option<usize>,
    stop_at_step: Option<u64>,
) -> Result<ExitCode, Failure> {
    let Some(path) = path else {
        return Err(input(
            "no scenario given: the built-in demo does not run on several ranks; allowed: mpirun -np N grains run SCENARIO.toml",
        ));
    };
    let src = Source::read(path).map_err(input)?;
    let threads = set_threads(threads)?;
    let scn = grains_sim::scenario::parse(&src).map_err(input)?;
    let out = out.unwrap_or_else(|| driver::default_out(scn.name()));
    driver::writable_out(&out).map_err(input)?;
    let leader = launch.rank == 0;
    let opts = options(leader, out, threads, stop_at_step);
    let (link, mpi) = world()?;
    ended(
        report(sim_run::run_on(&src, opts, link), leader),
        leader,
        mpi,
    )
}

/// The end of a run on one of several ranks: rank 0 prints its line now, then MPI is
/// finalised. Stopping a job on Ctrl-C, mpirun (OpenMPI 4.1) sends the ranks SIGTERM,
/// then SIGKILL a second later, and MPI_Finalize does not return meanwhile
/// (docs/parallel.md, "Signals under mpirun"): the line comes first, a signal during the
/// finalisation exits at once with the run's code, and an interrupted run gives the
/// finalisation half a second.
fn ended(done: Result<ExitCode, Failure>, leader: bool, mpi: Mpi) -> Result<ExitCode, Failure> {
    let (code, exit) = match done {
        Ok(exit) => (0, exit),
        Err((code, msg)) if leader => (code, super::fail(code, &msg)),
        Err((code, _)) => (code, ExitCode::from(code)),
    };
    super::interrupt::settle(code);
    if code == 130 {
        std::thread::spawn(|| {
            std::thread::sleep(std::time::Duration::from_millis(500));
            std::process::exit(130);
        });
    }
    drop(mpi);
    Ok(exit)
}

/// `grains resume DIR` on every rank of `launch`: each reads the checkpoint, whatever
/// rank count wrote it, and takes its box.
pub fn cmd_resume(
    launch: Launch,
    dir: &Path,
    threads: Option<usize>,
    stop_at_step: Option<u64>,
) -> Result<ExitCode, Failure> {
    let threads = set_threads(threads)?;
    let leader = launch.rank == 0;
    let opts = options(leader, dir.to_path_buf(), threads, stop_at_step);
    let (link, mpi) = world()?;
    ended(
        report(sim_run::resume_on(dir, opts, link), leader),
        leader,
        mpi,
    )
}

/// The options of a run on one of several ranks: rank 0 shows the progress.
fn options(
    leader: bool,
    out: PathBuf,
    threads: usize,
    stop_at_step: Option<u64>,
) -> RunOptions<'static> {
    RunOptions {
        out,
        threads,
        stop_at_step,
        // A signal reaches the ranks at different steps (or one rank only): the run
        // loop reads every rank's flag together and all stop at the same step.
        interrupt: Some(super::interrupt::install(leader)),
        progress: if leader {
            Box::new(progress::Bar::new())
        } else {
            Box::new(driver::Silent)
        },
    }
}

/// `grains bench dem` (2D) on every rank: rank 0 prints the report.
pub fn cmd_bench_dem(bed: bench::dem::Bed, steps: u64) -> Result<ExitCode, Failure> {
    let (link, _mpi) = world()?;
    if let Some(r) = bench::dem_ranks::run_on(&bed, steps, link).map_err(input)? {
        print!("{}", r.text());
    }
    Ok(ExitCode::SUCCESS)
}
