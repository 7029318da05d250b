//! Progress reporting: a bar with ETA on a terminal, plain lines every 10 % otherwise.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::time::Instant;

/// Reports how far a run of `total` steps has got.
pub struct Progress {
    bar: Option<ProgressBar>,
    total: u64,
    next_line: u64,
    started: Instant,
    stride: u64,
}

impl Progress {
    /// A bar on a terminal, plain lines on anything else.
    pub fn new(total: u64) -> Self {
        let bar = std::io::stderr().is_terminal().then(|| {
            let b = ProgressBar::new(total);
            b.set_style(
                ProgressStyle::with_template(
                    "{bar:40} {pos}/{len} steps  {elapsed} elapsed, ETA {eta}",
                )
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            b
        });
        Progress {
            bar,
            total,
            next_line: total / 10,
            started: Instant::now(),
            stride: (total / 500).max(1),
        }
    }

    /// Called after each step.
    pub fn tick(&mut self, step: u64) {
        if !step.is_multiple_of(self.stride) {
            return;
        }
        if let Some(b) = &self.bar {
            b.set_position(step);
        } else if step >= self.next_line && self.total > 0 {
            let pct = 100 * step / self.total;
            let secs = self.started.elapsed().as_secs_f64();
            let eta = secs * (self.total - step) as f64 / step.max(1) as f64;
            eprintln!(
                "  {pct:3}%  step {step}/{}  {secs:.1} s elapsed, ETA {eta:.1} s",
                self.total
            );
            self.next_line += (self.total / 10).max(1);
        }
    }

    /// Clears the bar.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}
