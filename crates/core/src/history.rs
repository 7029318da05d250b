//! Time histories: a CSV file written row by row, also kept in memory for
//! end-of-run plots and checks.
//!
//! Values are written in Rust's shortest round-trip scientific form
//! (`{:e}`, e.g. `1.5e-7`), so reading a history back gives bit-identical
//! numbers and tiny time steps stay readable; columns declared integer
//! (steps, counts) are written as integers.

use std::fs::File;
use std::io::{self, BufRead, BufReader, BufWriter, Write};
use std::path::Path;
use std::time::{Duration, Instant};

/// How long rows may sit in the buffer. Flushing every row would cost a
/// system call per time step; never flushing would hide progress from
/// anyone tailing the file and lose rows if the run is killed.
const FLUSH_INTERVAL: Duration = Duration::from_secs(1);

/// A CSV time history with a fixed set of named columns.
#[derive(Debug)]
pub struct History {
    columns: Vec<String>,
    integer: Vec<bool>,
    rows: Vec<Vec<f64>>,
    writer: BufWriter<File>,
    last_flush: Instant,
}

impl History {
    /// Creates (truncates) `path` and writes the header line.
    ///
    /// Column names must be non-empty, unique and free of commas, quotes
    /// and line breaks, so the file needs no CSV quoting.
    pub fn create(path: &Path, columns: &[&str]) -> io::Result<Self> {
        check_columns(columns)?;
        let named = |e: io::Error| {
            io::Error::new(e.kind(), format!("cannot write {}: {e}", path.display()))
        };
        let mut writer = BufWriter::new(File::create(path).map_err(named)?);
        writeln!(writer, "{}", columns.join(",")).map_err(named)?;
        writer.flush().map_err(named)?;
        Ok(Self {
            columns: columns.iter().map(|c| c.to_string()).collect(),
            integer: vec![false; columns.len()],
            rows: Vec::new(),
            writer,
            last_flush: Instant::now(),
        })
    }

    /// Declares the named columns integer-valued (steps, counts): their values are
    /// written as integers. Unknown names are ignored.
    pub fn integer_columns(mut self, names: &[&str]) -> Self {
        for (c, flag) in self.columns.iter().zip(self.integer.iter_mut()) {
            *flag |= names.contains(&c.as_str());
        }
        self
    }

    /// Appends a row (one value per column, non-finite values allowed and
    /// written as `NaN`/`inf`).
    pub fn push(&mut self, row: &[f64]) -> io::Result<()> {
        if row.len() != self.columns.len() {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!(
                    "history row has {} values but there are {} columns",
                    row.len(),
                    self.columns.len()
                ),
            ));
        }
        let mut line = String::with_capacity(row.len() * 24);
        for (i, v) in row.iter().enumerate() {
            if i > 0 {
                line.push(',');
            }
            if self.integer[i] && v.fract() == 0.0 && v.abs() < 9.0e15 {
                line.push_str(&format!("{}", *v as i64));
            } else {
                line.push_str(&format!("{v:e}"));
            }
        }
        line.push('\n');
        self.writer.write_all(line.as_bytes())?;
        self.rows.push(row.to_vec());
        if self.last_flush.elapsed() >= FLUSH_INTERVAL {
            self.flush()?;
        }
        Ok(())
    }

    /// Forces buffered rows to the file.
    pub fn flush(&mut self) -> io::Result<()> {
        self.last_flush = Instant::now();
        self.writer.flush()
    }

    /// All values of the named column, in row order.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let i = self.columns.iter().position(|c| c == name)?;
        Some(self.rows.iter().map(|r| r[i]).collect())
    }

    /// Column names, in file order.
    pub fn columns(&self) -> &[String] {
        &self.columns
    }

    /// All rows pushed so far.
    pub fn rows(&self) -> &[Vec<f64>] {
        &self.rows
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// True if no row has been pushed.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }
}

impl Drop for History {
    fn drop(&mut self) {
        // BufWriter would flush on drop too; doing it here documents that
        // a history dropped early (error path) still keeps its rows. An
        // error cannot be reported from drop.
        let _ = self.writer.flush();
    }
}

fn check_columns(columns: &[&str]) -> io::Result<()> {
    let bad = |msg: String| io::Error::new(io::ErrorKind::InvalidInput, msg);
    for (i, c) in columns.iter().enumerate() {
        if c.is_empty() || c.contains([',', '"', '\n', '\r']) {
            return Err(bad(format!("invalid history column name {c:?}")));
        }
        if columns[..i].contains(c) {
            return Err(bad(format!("duplicate history column name {c:?}")));
        }
    }
    Ok(())
}

/// Reads a history CSV: header names and rows of numbers.
///
/// Blank lines are skipped. A malformed row is an
/// [`io::ErrorKind::InvalidData`] error naming its line, except a last line
/// without its newline, which is what a killed run leaves and is dropped.
pub fn read_csv(path: &Path) -> io::Result<(Vec<String>, Vec<Vec<f64>>)> {
    let bad = |msg: String| io::Error::new(io::ErrorKind::InvalidData, msg);
    let mut reader = BufReader::new(File::open(path)?);
    let mut line = String::new();
    if reader.read_line(&mut line)? == 0 {
        return Err(bad(format!("{}: empty file, no header", path.display())));
    }
    let columns: Vec<String> = line
        .trim_end_matches(['\n', '\r'])
        .split(',')
        .map(|s| s.trim().to_string())
        .collect();
    let mut rows = Vec::new();
    let mut lineno = 1;
    loop {
        line.clear();
        if reader.read_line(&mut line)? == 0 {
            break;
        }
        lineno += 1;
        let complete = line.ends_with('\n');
        let text = line.trim_end_matches(['\n', '\r']);
        if text.trim().is_empty() {
            continue;
        }
        match parse_row(text, columns.len()) {
            Some(row) => rows.push(row),
            None if !complete => break,
            None => {
                return Err(bad(format!(
                    "{}:{lineno}: expected {} numbers, got {text:?}",
                    path.display(),
                    columns.len()
                )))
            }
        }
    }
    Ok((columns, rows))
}

fn parse_row(text: &str, n: usize) -> Option<Vec<f64>> {
    let row: Vec<f64> = text
        .split(',')
        .map(|s| s.trim().parse::<f64>().ok())
        .collect::<Option<_>>()?;
    (row.len() == n).then_some(row)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("grains-core-hist-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn round_trips_exactly() {
        let p = scratch("h.csv");
        let mut h = History::create(&p, &["t", "energy", "ratio"]).unwrap();
        assert!(h.is_empty());
        let rows = [
            [0.0, 1.0 / 3.0, -0.0],
            [1e-7, 123456.789e10, f64::MIN_POSITIVE],
            [2e-7, f64::NAN, f64::INFINITY],
        ];
        for r in &rows {
            h.push(r).unwrap();
        }
        h.flush().unwrap();
        assert_eq!(h.len(), 3);
        assert_eq!(h.column("t").unwrap(), vec![0.0, 1e-7, 2e-7]);
        assert!(h.column("nope").is_none());
        assert_eq!(h.columns(), ["t", "energy", "ratio"]);

        let (cols, back) = read_csv(&p).unwrap();
        assert_eq!(cols, ["t", "energy", "ratio"]);
        assert_eq!(back.len(), 3);
        for (a, b) in back.iter().zip(&rows) {
            for (x, y) in a.iter().zip(b) {
                assert!(x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan()));
            }
        }
        let text = std::fs::read_to_string(&p).unwrap();
        assert!(text.contains("\n1e-7,"), "{text}");
    }

    #[test]
    fn integer_columns_are_written_as_integers() {
        let p = scratch("int.csv");
        let mut h = History::create(&p, &["time", "step", "contacts"])
            .unwrap()
            .integer_columns(&["step", "contacts"]);
        h.push(&[1.5e-7, 120.0, f64::NAN]).unwrap();
        h.flush().unwrap();
        let text = std::fs::read_to_string(&p).unwrap();
        assert_eq!(text, "time,step,contacts\n1.5e-7,120,NaN\n");
        let (_, rows) = read_csv(&p).unwrap();
        assert_eq!(rows[0][1], 120.0);
    }

    #[test]
    fn wrong_row_length_is_an_error() {
        let p = scratch("len.csv");
        let mut h = History::create(&p, &["a", "b"]).unwrap();
        let e = h.push(&[1.0]).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::InvalidInput);
        assert!(h.is_empty());
    }

    #[test]
    fn bad_column_names_are_rejected() {
        let p = scratch("cols.csv");
        assert!(History::create(&p, &["a,b"]).is_err());
        assert!(History::create(&p, &["a", "a"]).is_err());
        assert!(History::create(&p, &[""]).is_err());
    }

    #[test]
    fn reader_drops_torn_last_line_but_rejects_bad_rows() {
        let p = scratch("torn.csv");
        std::fs::write(&p, "t,x\n0e0,1e0\n\n1e0,2e0\n2e0,3.").unwrap();
        let (_, rows) = read_csv(&p).unwrap();
        assert_eq!(rows, vec![vec![0.0, 1.0], vec![1.0, 2.0], vec![2.0, 3.0]]);
        std::fs::write(&p, "t,x\n0e0,1e0\n1e0\n2e0,3e0\n").unwrap();
        let e = read_csv(&p).unwrap_err();
        assert!(e.to_string().contains(":3:"), "{e}");
        std::fs::write(&p, "t,x\n0e0,1e0\n2e0,3e").unwrap();
        assert_eq!(read_csv(&p).unwrap().1.len(), 1);
        std::fs::write(&p, "").unwrap();
        assert!(read_csv(&p).is_err());
    }
}
