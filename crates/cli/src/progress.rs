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
    /// The fraction done when the current bar started: a resumed run starts part way,
    /// and its ETA must come from the progress made since, not from the whole run's.
    start_done: Option<f64>,
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
            start_done: None,
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
        self.start_done = None;
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
        let first = self.start_done.is_none();
        let start = *self.start_done.get_or_insert(done);
        if let Some(b) = &self.bar {
            if permille != b.position() {
                b.set_position(permille);
                b.set_message(msg());
            }
            if first {
                // The jump to where a resumed run stands is not progress made.
                b.reset_eta();
            }
        } else if done >= self.next_line {
            let secs = self.started.elapsed().as_secs_f64();
            let eta = eta(secs, done, start).map_or("–".into(), |e| format!("{e:.1} s"));
            eprintln!(
                "  {:3.0}%  {}  {secs:.1} s elapsed, ETA {eta}",
                100.0 * done,
                msg()
            );
            while self.next_line <= done {
                self.next_line += 0.1;
            }
        }
    }
}

/// Time left at the rate of the progress made since `start` (the fraction done when the
/// clock started); none before any progress.
fn eta(secs: f64, done: f64, start: f64) -> Option<f64> {
    let made = done - start;
    (made > 0.0).then(|| secs * (1.0 - done) / made)
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

#[cfg(test)]
mod tests {
    use super::eta;

    #[test]
    fn eta_of_a_resumed_run_counts_only_progress_since_the_resume() {
        // Resumed at half way, 10 % more done in 60 s: 40 % left takes 240 s.
        let e = eta(60.0, 0.6, 0.5).unwrap();
        assert!((e - 240.0).abs() < 1e-9, "{e}");
        assert_eq!(eta(5.0, 0.5, 0.5), None);
        assert!((eta(10.0, 0.25, 0.0).unwrap() - 30.0).abs() < 1e-9);
    }
}
