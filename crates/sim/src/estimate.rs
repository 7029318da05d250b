//! What a run will cost, known before anything is built: particles, steps, memory and
//! wall time. `grains check` prints it; `run`, `check` and `bench` refuse a run that
//! cannot fit in memory before they allocate it.

use serde::Serialize;

/// Particle-steps per second and thread that each engine sustains on a 2-core AMD EPYC
/// (BENCHMARKS.md, 2026-11-21): the 100 k DEM bed (1.9e7), the cylinder-bounce MPM
/// examples (3e6 per point-step with a grid's worth of overhead), the FEM–DEM rings
/// (1.6e7 per thread for test 2, 6.5e6 for the coarse small ring, whose charge and
/// rebuilds weigh more: 1.0e7 is within a factor 2 of both).
pub mod rate {
    /// DEM.
    pub const DEM: f64 = 1.9e7;
    /// MPM (material point steps).
    pub const MPM: f64 = 3.0e6;
    /// FEM–DEM (particle steps; the charge's elements ride along).
    pub const FEM_DEM: f64 = 1.0e7;
}

/// Wall time of a step beyond its particles' work: starting the parallel passes and the
/// bookkeeping between them (about a microsecond for a handful of particles).
pub const STEP_OVERHEAD_S: f64 = 1e-6;

/// Runs estimated to take longer than this (s) get a warning.
pub const LONG_RUN_S: f64 = 86400.0;

/// What a run will cost.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Estimate {
    /// Particles (material points for MPM).
    pub particles: u64,
    /// Steps: exact for a fixed step, else an upper bound the run does not exceed.
    pub steps: u64,
    /// Peak memory (bytes).
    pub memory_bytes: u64,
    /// Wall time on `threads` threads (s).
    pub wall_time_s: f64,
    /// Threads the wall time is for.
    pub threads: usize,
}

impl Estimate {
    /// The estimate for `particles` particles over `steps` steps at `rate`
    /// particle-steps per second and thread, on `threads` threads.
    pub fn new(particles: u64, steps: u64, memory_bytes: u64, rate: f64, threads: usize) -> Self {
        // Two threads gain 1.9× on the DEM bed (BENCHMARKS.md); assume the same
        // efficiency for more.
        let speedup = 1.0 + 0.9 * (threads.max(1) - 1) as f64;
        Estimate {
            particles,
            steps,
            memory_bytes,
            wall_time_s: particles as f64 * steps as f64 / (rate * speedup)
                + steps as f64 * STEP_OVERHEAD_S,
            threads,
        }
    }

    /// Refuses a run that would not fit in the memory available now, naming the
    /// estimate; `what` names the input that sets the size.
    pub fn fits_memory(&self, what: &str) -> Result<(), String> {
        match available_memory() {
            Some(avail) if self.memory_bytes > avail => Err(format!(
                "{what}: about {} particles need about {} of memory, {} is available; make the run smaller",
                self.particles,
                bytes(self.memory_bytes),
                bytes(avail)
            )),
            _ => Ok(()),
        }
    }

    /// A warning for a run that will take very long, if it will.
    pub fn warning(&self) -> Option<String> {
        (self.wall_time_s > LONG_RUN_S).then(|| {
            format!(
                "this run takes {} steps, about {} on {} threads",
                self.steps,
                duration(self.wall_time_s),
                self.threads
            )
        })
    }
}

/// Memory the system can give without swapping (Linux `MemAvailable`), in bytes.
pub fn available_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Bytes as MB or GB.
pub fn bytes(b: u64) -> String {
    if b >= 1 << 30 {
        format!("{:.1} GB", b as f64 / (1u64 << 30) as f64)
    } else {
        format!("{:.1} MB", b as f64 / 1e6)
    }
}

/// Seconds as s, min, h or days.
pub fn duration(s: f64) -> String {
    if !s.is_finite() {
        "forever".into()
    } else if s < 120.0 {
        format!("{s:.1} s")
    } else if s < 7200.0 {
        format!("{:.1} min", s / 60.0)
    } else if s < 3.0 * 86400.0 {
        format!("{:.1} h", s / 3600.0)
    } else {
        format!("{:.3e} days", s / 86400.0)
    }
}

/// Counts the data lines of a packing file (`x y r`, `#` comments) without parsing
/// them, or `None` if it cannot be read.
pub fn packing_lines(path: &std::path::Path) -> Option<u64> {
    use std::io::BufRead;
    let f = std::fs::File::open(path).ok()?;
    let mut n = 0;
    for line in std::io::BufReader::new(f).lines() {
        let line = line.ok()?;
        let t = line.trim();
        if !t.is_empty() && !t.starts_with('#') {
            n += 1;
        }
    }
    Some(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_huge_run_does_not_fit() {
        let e = Estimate::new(10_000_000_000, 10, u64::MAX / 2, rate::DEM, 2);
        let m = e.fits_memory("particles[0].count").unwrap_err();
        assert!(
            m.starts_with("particles[0].count: about 10000000000 particles"),
            "{m}"
        );
        assert!(Estimate::new(10, 1_000_000_000_000_000, 1000, rate::DEM, 2)
            .warning()
            .is_some());
        assert!(Estimate::new(1000, 1000, 1000, rate::DEM, 2)
            .warning()
            .is_none());
    }
}
