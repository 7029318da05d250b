//! `grains bench dem`: time the DEM engine on a dense bed with the peer benchmark's
//! physics (LAMMPS `gran/hooke/history`, kn = 4000, kt = 2/7 kn, γn = 87, γt = γn/2,
//! μ = 0.3, density 1, g = 1, Δt = 5·10⁻⁴, skin 0.1, frictional floor, periodic x).

use crate::{fail, set_threads};
use clap::Subcommand;
use glam::DVec2;
use grains_core::rng;
use grains_dem::{step, ContactModel, Domain, Material, Particles, Setup, State, Wall, WallShape};
use rand::RngExt;
use std::process::ExitCode;
use std::time::Instant;

/// What to benchmark.
#[derive(Subcommand)]
pub enum BenchCommand {
    /// The DEM engine on a bed of disks.
    Dem {
        /// Number of disks in a bed grains builds itself (ignored with --lammps-data).
        #[arg(long, default_value_t = 20_000)]
        particles: usize,
        /// Start from this LAMMPS data file (atom_style sphere), as the peer benchmark does.
        #[arg(long)]
        lammps_data: Option<std::path::PathBuf>,
        /// Repeat the data file's bed this many times side by side along x (a wider bed
        /// with the same contact statistics: 18 × the 100 k bed is 1.8 M disks).
        #[arg(long, default_value_t = 1)]
        tile: usize,
        /// Timed steps.
        #[arg(long, default_value_t = 2000)]
        steps: u64,
        /// Worker threads.
        #[arg(long)]
        threads: Option<usize>,
    },
    /// The MPM engine: an elastic block (or two in contact) falling in a walled box.
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
        /// Shape function: linear, gimp or bspline2 (default: the peer's quadratic B-spline).
        #[arg(long, default_value = "bspline2")]
        shape: String,
        /// Stress update: usf, usl, usavg or musl (default: USL, two passes like the peer).
        #[arg(long, default_value = "usl")]
        update: String,
    },
}

/// Runs the command.
pub fn cmd_bench(what: BenchCommand) -> ExitCode {
    match what {
        BenchCommand::Mpm {
            particles,
            grid,
            steps,
            threads,
            bodies,
            shape,
            update,
        } => crate::mpm::bench::run(crate::mpm::bench::Options {
            particles,
            grid,
            steps,
            threads,
            bodies,
            shape,
            update,
        }),
        BenchCommand::Dem {
            particles,
            lammps_data,
            tile,
            steps,
            threads,
        } => {
            if tile == 0 {
                return fail(1, "--tile = 0: must be at least 1");
            }
            let threads = match set_threads(threads) {
                Ok(t) => t,
                Err(e) => return fail(1, &e),
            };
            let (setup, p) = match &lammps_data {
                Some(path) => match lammps_bed(path, tile) {
                    Ok(v) => v,
                    Err(e) => return fail(1, &e),
                },
                None if particles == 0 => return fail(1, "--particles = 0: must be at least 1"),
                None => peer_bed(particles),
            };
            let particles = p.len();
            let mut state = State::new(&setup, p);
            let t0 = Instant::now();
            let c0 = cpu_seconds();
            // Step from inside the pool: parallel passes then start on a worker thread
            // instead of waking the pool from outside three times a step.
            rayon::scope(|_| {
                for _ in 0..steps {
                    step(&setup, &mut state);
                }
            });
            let secs = t0.elapsed().as_secs_f64();
            let cpu = c0.and_then(|c0| Some(cpu_seconds()? - c0));
            let rate = particles as f64 * steps as f64 / secs;
            println!("particles: {particles}");
            println!("steps: {steps}");
            println!("threads: {threads}");
            println!("wall time: {secs:.3} s");
            if let Some(cpu) = cpu {
                // Robust to other load on the machine: time the process was not running
                // is not counted.
                println!("cpu time: {cpu:.3} s");
                println!(
                    "particle-steps per cpu-s: {:.4e}",
                    particles as f64 * steps as f64 / cpu
                );
            }
            println!("neighbour builds: {}", state.contacts.builds);
            let d = grains_dem::diagnostics::measure(&setup, &state);
            println!(
                "list entries per particle: {:.3}, contacts per particle: {:.3}",
                state.contacts.len() as f64 / particles as f64,
                d.mean_coordination(particles)
            );
            println!(
                "state-hash: {:016x}",
                grains_dem::diagnostics::state_hash(&state)
            );
            if let Some(mb) = peak_memory_mb() {
                println!("peak memory: {mb:.0} MB");
            }
            println!("particle-steps/s: {rate:.4e}");
            ExitCode::SUCCESS
        }
    }
}

/// The peer benchmark's physics in a box `lo..hi`, periodic in x, floor at y = 0.
fn peer_setup(lo: DVec2, hi: DVec2) -> Setup {
    let material = Material {
        name: "bench".into(),
        density: 1.0,
        youngs: None,
        poisson: None,
        restitution: None,
        friction: None,
        // LAMMPS `fix nve/sphere` (no `disc` keyword) integrates rotation with I = 0.4 m r².
        inertia_factor: 0.4,
    };
    let model = ContactModel::HookeHistory {
        kn: 4000.0,
        kt: 4000.0 * 2.0 / 7.0,
        gamma_n: 87.0,
        gamma_t: 43.5,
        mu: 0.3,
        limit_damping: false,
    };
    let domain = Domain {
        lo,
        hi,
        periodic: [true, false],
    };
    let floor = Wall {
        name: "floor".into(),
        shape: WallShape::Segment {
            a: [-1e9, 0.0],
            b: [1e9, 0.0],
        },
        material: None,
    };
    Setup::new(
        domain,
        vec![material],
        model,
        vec![floor],
        DVec2::new(0.0, -1.0),
        5e-4,
        0.1,
    )
    .expect("the benchmark set-up is valid")
}

/// A bed of `n` disks (d uniform in [0.88, 0.98)) on a square lattice of pitch 1 over a
/// floor, about 2.3 times wider than high, with the peer benchmark's contact law.
pub fn peer_bed(n: usize) -> (Setup, Particles) {
    let nx = ((2.27 * n as f64).sqrt().ceil() as usize).max(4);
    let ny = n.div_ceil(nx);
    let setup = peer_setup(DVec2::ZERO, DVec2::new(nx as f64, ny as f64 + 2.0));
    let mut rng = rng::seeded(4711);
    let mut p = Particles::default();
    for k in 0..n {
        let at = DVec2::new((k % nx) as f64 + 0.5, (k / nx) as f64 + 0.5);
        let d = 0.88 + 0.1 * rng.random::<f64>();
        p.push(at, 0.5 * d, 1.0, 0.4, 0, DVec2::ZERO, 0.0);
    }
    (setup, p)
}

/// The bed of a LAMMPS data file with the peer benchmark's physics: disc masses of
/// density 1 (as `set density/disc 1.0` in `in.bench.lmp`), positions, velocities and
/// angular velocities from the file, the box's x bounds as the periodic length.
pub fn lammps_bed(path: &std::path::Path, tile: usize) -> Result<(Setup, Particles), String> {
    let data = grains_core::lammps_data::read(path).map_err(|e| e.to_string())?;
    if data.atoms.is_empty() {
        return Err(format!("{}: no atoms", path.display()));
    }
    let top = data
        .atoms
        .iter()
        .map(|a| a.pos[1])
        .fold(data.hi[1], f64::max);
    let width = data.hi[0] - data.lo[0];
    let setup = peer_setup(
        DVec2::new(data.lo[0], data.lo[1].min(0.0)),
        DVec2::new(data.lo[0] + width * tile as f64, top + 1.0),
    );
    let mut p = Particles::default();
    for k in 0..tile {
        for a in &data.atoms {
            if !(a.diameter.is_finite() && a.diameter > 0.0) {
                return Err(format!(
                    "{}: atom {} has diameter {}: must be > 0",
                    path.display(),
                    a.id,
                    a.diameter
                ));
            }
            // Fold into the file's own periodic box, then shift to copy k.
            let x = data.lo[0] + (a.pos[0] - data.lo[0]).rem_euclid(width) + width * k as f64;
            p.push(
                DVec2::new(x, a.pos[1]),
                0.5 * a.diameter,
                1.0,
                0.4,
                0,
                DVec2::new(a.vel[0], a.vel[1]),
                a.omega[2],
            );
        }
    }
    Ok((setup, p))
}

/// Peak resident memory of this process (Linux `VmHWM`), in MB.
fn peak_memory_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// CPU time of this process, all threads (s), from /proc/self/stat (utime + stime, in
/// clock ticks of 1/100 s); `None` where that file does not exist.
pub fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the parenthesised command name; utime and stime are fields 14 and 15.
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}
