//! `grains bench`: the engines timed on the peers' problems, printing `key: value`
//! lines and, last, `particle-steps/s: X`.

pub mod dem;
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
