//! `history.csv`: one row per sample, named columns in SI units, written as the run
//! goes and kept in memory for the end-of-run plots and checks.

use crate::driver::{Observer, Simulation};
use anyhow::Context;
use grains_core::history::{read_csv, History};
use std::path::Path;

/// A simulation that writes a history.
pub trait Recorded: Simulation {
    /// Column names, `time` and `step` first.
    fn columns(&self) -> Vec<String>;
    /// The integer-valued columns among them (steps, counts).
    fn integer_columns(&self) -> Vec<String> {
        vec!["step".into()]
    }
    /// One row for a sample, in column order.
    fn row(&self, sample: &Self::Sample) -> Vec<f64>;
}

/// Writes `history.csv`.
pub struct HistoryRecorder {
    /// The rows so far.
    pub history: History,
}

impl HistoryRecorder {
    /// Creates `out/history.csv` with the first row, measured now.
    pub fn create<S: Recorded>(out: &Path, sim: &mut S) -> anyhow::Result<Self> {
        Self::first_row(open(&out.join("history.csv"), sim)?, sim)
    }

    /// A history written nowhere (a rank other than 0 of a run spread over ranks).
    /// A `fresh` run's first row is measured now, as [`HistoryRecorder::create`]
    /// measures it, a resumed run's not, as [`HistoryRecorder::reopen`]: a sample there
    /// is taken by every rank together.
    pub fn discarding<S: Recorded>(sim: &mut S, fresh: bool) -> anyhow::Result<Self> {
        let null = if cfg!(windows) { "NUL" } else { "/dev/null" };
        let history = open(Path::new(null), sim)?;
        match fresh {
            true => Self::first_row(history, sim),
            false => Ok(HistoryRecorder { history }),
        }
    }

    fn first_row<S: Recorded>(mut history: History, sim: &mut S) -> anyhow::Result<Self> {
        let sample = sim.sample();
        history.push(&sim.row(&sample))?;
        Ok(HistoryRecorder { history })
    }

    /// Reopens the history of a run continued from a checkpoint at `step`, keeping the
    /// rows up to it (a run may have gone on past its last checkpoint before it stopped).
    pub fn reopen<S: Recorded>(out: &Path, sim: &S, step: u64) -> anyhow::Result<Self> {
        let path = out.join("history.csv");
        let (names, rows) =
            read_csv(&path).with_context(|| format!("cannot read {}", path.display()))?;
        if names != sim.columns() {
            anyhow::bail!("{}: columns differ from this scenario's", path.display());
        }
        let mut history = open(&path, sim)?;
        for row in rows.iter().filter(|r| r[1] <= step as f64) {
            history.push(row)?;
        }
        Ok(HistoryRecorder { history })
    }
}

fn open<S: Recorded>(path: &Path, sim: &S) -> anyhow::Result<History> {
    let columns = sim.columns();
    let names: Vec<&str> = columns.iter().map(String::as_str).collect();
    let integer = sim.integer_columns();
    let integer: Vec<&str> = integer.iter().map(String::as_str).collect();
    // The error names the path already.
    Ok(History::create(path, &names)?.integer_columns(&integer))
}

impl<S: Recorded> Observer<S> for HistoryRecorder {
    fn on_sample(&mut self, sim: &S, sample: &S::Sample) -> anyhow::Result<crate::driver::Flow> {
        self.history.push(&sim.row(sample))?;
        Ok(crate::driver::Flow::Continue)
    }

    fn on_end(
        &mut self,
        _sim: &S,
        _status: &crate::driver::Status,
        _report: &mut crate::driver::Report,
    ) -> anyhow::Result<()> {
        self.history.flush()?;
        Ok(())
    }

    fn persist(&mut self) -> anyhow::Result<()> {
        self.history.flush()?;
        Ok(())
    }
}
