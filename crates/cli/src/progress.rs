//! Progress on the terminal: a bar with ETA, or plain lines every 10 % when stderr is
//! not a terminal (batch jobs, logs).

use grains_sim::driver::{Clock, Progress};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::time::Instant;

/// The CLI's progress display.
pub struct Bar {
    bar: Option<ProgressBar>,
    next_line: f64,
    started: Instant,
}

impl Bar {
    /// A bar on a terminal, plain lines on anything else.
    pub fn new() -> Self {
        let bar = std::io::stderr().is_terminal().then(|| {
            let b = ProgressBar::new(1000);
            b.set_style(
                ProgressStyle::with_template(
                    "{bar:40} {percent:>3}%  {msg}  {elapsed} elapsed, ETA {eta}",
                )
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            b
        });
        Bar {
            bar,
            next_line: 0.1,
            started: Instant::now(),
        }
    }
}

impl Progress for Bar {
    fn announce(&mut self, line: &str) {
        eprintln!("grains: {line}");
    }

    fn update(&mut self, done: f64, c: Clock) {
        let permille = (1000.0 * done.clamp(0.0, 1.0)) as u64;
        if let Some(b) = &self.bar {
            if permille != b.position() {
                b.set_position(permille);
                b.set_message(format!("step {}, t = {:.4e} s", c.step, c.time));
            }
        } else if done >= self.next_line {
            let secs = self.started.elapsed().as_secs_f64();
            let eta = secs * (1.0 - done) / done.max(1e-9);
            eprintln!(
                "  {:3.0}%  step {}  t = {:.4e} s  {secs:.1} s elapsed, ETA {eta:.1} s",
                100.0 * done,
                c.step,
                c.time
            );
            self.next_line += 0.1;
        }
    }

    fn finish(&mut self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}
