//! `grains bench`: the engines timed on the peers' problems, printing `key: value`
//! lines and, last, `particle-steps/s: X`.

pub mod dem;
pub mod dem3d;
pub mod dem_ranks;
pub mod mpm;

/// What a benchmark measured.
#[derive(Clone, Debug, Default)]
pub struct Report {
    /// `key: value` lines, in print order.
    pub lines: Vec<(String, String)>,
    /// Particle-steps per wall-clock second.
    pub rate: f64,
}

impl Report {
    fn line(&mut self, key: &str, value: impl ToString) {
        self.lines.push((key.into(), value.to_string()));
    }

    /// The report as printed, ending with `particle-steps/s: X`.
    pub fn text(&self) -> String {
        let mut s = String::new();
        for (k, v) in &self.lines {
            s.push_str(&format!("{k}: {v}\n"));
        }
        s.push_str(&format!("particle-steps/s: {:.4e}\n", self.rate));
        s
    }
}

/// Runs `steps` calls of `step` and starts the report with the timing lines (particles,
/// steps, threads, wall and CPU time); the rate is particle-steps per wall-clock second.
pub fn timed(particles: usize, steps: u64, mut step: impl FnMut() + Send) -> Report {
    let threads = rayon::current_num_threads();
    let t0 = std::time::Instant::now();
    let c0 = cpu_seconds();
    // Step from inside the pool: parallel passes then start on a worker thread instead
    // of waking the pool from outside three times a step.
    rayon::scope(|_| {
        for _ in 0..steps {
            step();
        }
    });
    let secs = t0.elapsed().as_secs_f64();
    let cpu = c0.and_then(|c0| Some(cpu_seconds()? - c0));
    let work = particles as f64 * steps as f64;
    let mut r = Report::default();
    r.line("particles", particles);
    r.line("steps", steps);
    r.line("threads", threads);
    r.line("wall time", format!("{secs:.3} s"));
    if let Some(cpu) = cpu {
        // Robust to other load on the machine: time the process was not running is not
        // counted.
        r.line("cpu time", format!("{cpu:.3} s"));
        r.line("particle-steps per cpu-s", format!("{:.4e}", work / cpu));
    }
    r.rate = work / secs;
    r
}

/// Peak resident memory of this process (Linux `VmHWM`), in MB.
pub fn peak_memory_mb() -> Option<f64> {
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
