//! Progress on the terminal: a bar with ETA, or plain lines every 10 % when stderr is
//! not a terminal (batch jobs, logs). A stage before the run (making its packing) gets
//! a bar of its own.

use grains_sim::driver::{Clock, Progress};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::time::Instant;

/// The CLI's progress display.
pub struct Bar {
    terminal: bool,
    bar: Option<ProgressBar>,
    /// What the current bar is for: `None` for the run itself.
    stage: Option<String>,
    next_line: f64,
    started: Instant,
}

impl Bar {
    /// A bar on a terminal, plain lines on anything else.
    pub fn new() -> Self {
        Bar {
            terminal: std::io::stderr().is_terminal(),
            bar: None,
            stage: None,
            next_line: 0.1,
            started: Instant::now(),
        }
    }

    /// A line above the bar.
    pub fn println(&self, line: &str) {
        match &self.bar {
            Some(b) => b.suspend(|| eprintln!("{line}")),
            None => eprintln!("{line}"),
        }
    }

    /// Starts a fresh bar (and ETA) when what is being tracked changes.
    fn track(&mut self, stage: Option<&str>) {
        if self.stage.as_deref() == stage && (self.bar.is_some() || !self.terminal) {
            return;
        }
        if let Some(b) = self.bar.take() {
            b.finish_and_clear();
        }
        self.stage = stage.map(String::from);
        self.next_line = 0.1;
        self.started = Instant::now();
        if self.terminal {
            let b = ProgressBar::new(1000);
            b.set_style(
                ProgressStyle::with_template(
                    "{bar:40} {percent:>3}%  {msg}  {elapsed} elapsed, ETA {eta}",
                )
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            self.bar = Some(b);
        }
    }

    fn show(&mut self, done: f64, msg: impl FnOnce() -> String) {
        let permille = (1000.0 * done.clamp(0.0, 1.0)) as u64;
        if let Some(b) = &self.bar {
            if permille != b.position() {
                b.set_position(permille);
                b.set_message(msg());
            }
        } else if done >= self.next_line {
            let secs = self.started.elapsed().as_secs_f64();
            let eta = secs * (1.0 - done) / done.max(1e-9);
            eprintln!(
                "  {:3.0}%  {}  {secs:.1} s elapsed, ETA {eta:.1} s",
                100.0 * done,
                msg()
            );
            while self.next_line <= done {
                self.next_line += 0.1;
            }
        }
    }
}

impl Progress for Bar {
    fn announce(&mut self, line: &str) {
        self.println(&format!("grains: {line}"));
    }

    fn update(&mut self, done: f64, c: Clock) {
        self.track(None);
        self.show(done, || format!("step {}, t = {:.4e} s", c.step, c.time));
    }

    fn stage(&mut self, what: &str, done: f64) {
        self.track(Some(what));
        self.show(done, || what.to_string());
    }

    fn finish(&mut self) {
        if let Some(b) = self.bar.take() {
            b.finish_and_clear();
        }
    }
}
