//! `.pvd` collections: the index that lets ParaView open a run's frames as
//! one time series.
//!
//! The whole file is rewritten atomically after every push, so a run killed
//! at any moment leaves a valid series of the frames written so far. The
//! rewrite is linear in the number of entries, which is negligible next to
//! writing the frames themselves.

use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};

use crate::atomic::write_atomic;
use crate::xml::{attr, escape_attr, invalid, tags, Tag};

/// One dataset of the collection.
#[derive(Clone, Debug, PartialEq)]
pub struct PvdEntry {
    /// Simulation time of the frame.
    pub time: f64,
    /// Index of the dataset within its timestep (particles 0, walls 1, ...).
    pub part: usize,
    /// Block name shown by ParaView for grouped datasets.
    pub name: Option<String>,
    /// Data file, relative to the `.pvd`.
    pub file: String,
}

/// A `.pvd` time series being written.
#[derive(Clone, Debug)]
pub struct PvdSeries {
    path: PathBuf,
    entries: Vec<PvdEntry>,
}

impl PvdSeries {
    /// An empty series that will be written to `path` on the first push.
    pub fn new(path: &Path) -> Self {
        Self {
            path: path.to_path_buf(),
            entries: Vec::new(),
        }
    }

    /// Reopens an existing `.pvd` (e.g. to continue a restarted run).
    pub fn load(path: &Path) -> io::Result<Self> {
        let text = std::fs::read_to_string(path)?;
        let mut entries = Vec::new();
        for tag in tags(&text)? {
            let Tag::Open { name, attrs, .. } = tag else {
                continue;
            };
            if name != "DataSet" {
                continue;
            }
            let time = attr(&attrs, "timestep")
                .unwrap_or("0")
                .parse::<f64>()
                .map_err(|_| invalid(format!("{}: bad timestep", path.display())))?;
            let part = attr(&attrs, "part")
                .unwrap_or("0")
                .parse::<usize>()
                .map_err(|_| invalid(format!("{}: bad part", path.display())))?;
            let file = attr(&attrs, "file")
                .ok_or_else(|| invalid(format!("{}: DataSet without file", path.display())))?
                .to_string();
            entries.push(PvdEntry {
                time,
                part,
                name: attr(&attrs, "name").map(str::to_string),
                file,
            });
        }
        Ok(Self {
            path: path.to_path_buf(),
            entries,
        })
    }

    /// Adds one dataset at `time` and rewrites the `.pvd`.
    pub fn push(&mut self, time: f64, relative_file: &str) -> io::Result<()> {
        check_time(time)?;
        self.entries.push(PvdEntry {
            time,
            part: 0,
            name: None,
            file: relative_file.to_string(),
        });
        self.write()
    }

    /// Adds several datasets sharing `time`, as parts 0, 1, ... named after
    /// `(name, file)` pairs, and rewrites the `.pvd` once. ParaView shows
    /// each timestep as one multiblock dataset.
    pub fn push_group(&mut self, time: f64, parts: &[(&str, &str)]) -> io::Result<()> {
        check_time(time)?;
        for (part, (name, file)) in parts.iter().enumerate() {
            self.entries.push(PvdEntry {
                time,
                part,
                name: Some(name.to_string()),
                file: file.to_string(),
            });
        }
        self.write()
    }

    /// Drops entries later than `time` (a restart from an earlier frame)
    /// and rewrites the `.pvd`.
    pub fn truncate_after(&mut self, time: f64) -> io::Result<()> {
        self.entries.retain(|e| e.time <= time);
        self.write()
    }

    /// The entries so far.
    pub fn entries(&self) -> &[PvdEntry] {
        &self.entries
    }

    /// Where the `.pvd` is written.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The XML text of the collection.
    pub fn to_xml(&self) -> String {
        let mut s = String::with_capacity(200 + 120 * self.entries.len());
        s.push_str("<?xml version=\"1.0\"?>\n");
        s.push_str("<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n");
        s.push_str("  <Collection>\n");
        for e in &self.entries {
            // `{:e}` is the shortest representation that parses back to the
            // same f64, and stays compact for tiny time steps.
            let _ = write!(
                s,
                "    <DataSet timestep=\"{:e}\" group=\"\" part=\"{}\"",
                e.time, e.part
            );
            if let Some(name) = &e.name {
                let _ = write!(s, " name=\"{}\"", escape_attr(name));
            }
            let _ = writeln!(s, " file=\"{}\"/>", escape_attr(&e.file));
        }
        s.push_str("  </Collection>\n</VTKFile>\n");
        s
    }

    fn write(&self) -> io::Result<()> {
        write_atomic(&self.path, self.to_xml().as_bytes())
    }
}

fn check_time(time: f64) -> io::Result<()> {
    if time.is_finite() {
        Ok(())
    } else {
        Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("pvd timestep must be finite, got {time}"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("grains-core-pvd-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn every_push_leaves_a_complete_file() {
        let p = scratch("single.pvd");
        let mut s = PvdSeries::new(&p);
        s.push(0.0, "frames/p_0000.vtp").unwrap();
        let first = std::fs::read_to_string(&p).unwrap();
        assert!(first.trim_end().ends_with("</VTKFile>"));
        assert_eq!(first.matches("<DataSet").count(), 1);
        s.push(0.1 + 0.2, "frames/p_0001.vtp").unwrap();
        let back = PvdSeries::load(&p).unwrap();
        assert_eq!(back.entries(), s.entries());
        assert_eq!(back.entries()[1].time, 0.1 + 0.2);
        assert_eq!(back.path(), p.as_path());
    }

    #[test]
    fn groups_share_time_and_number_parts() {
        let p = scratch("group.pvd");
        let mut s = PvdSeries::new(&p);
        s.push_group(1e-7, &[("particles", "p_1.vtp"), ("walls", "w & 1.vtp")])
            .unwrap();
        s.push_group(2e-7, &[("particles", "p_2.vtp"), ("walls", "w_2.vtp")])
            .unwrap();
        let text = std::fs::read_to_string(&p).unwrap();
        assert!(text.contains("timestep=\"1e-7\" group=\"\" part=\"1\" name=\"walls\""));
        assert!(text.contains("file=\"w &amp; 1.vtp\""), "{text}");
        let back = PvdSeries::load(&p).unwrap();
        assert_eq!(back.entries().len(), 4);
        assert_eq!(back.entries()[1].file, "w & 1.vtp");
        assert_eq!(back.entries()[3].part, 1);
    }

    #[test]
    fn truncate_and_invalid_time() {
        let p = scratch("trunc.pvd");
        let mut s = PvdSeries::new(&p);
        for i in 0..5 {
            s.push(i as f64, &format!("f{i}.vtp")).unwrap();
        }
        s.truncate_after(2.0).unwrap();
        assert_eq!(PvdSeries::load(&p).unwrap().entries().len(), 3);
        let e = s.push(f64::NAN, "x.vtp").unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::InvalidInput);
        assert_eq!(s.entries().len(), 3);
    }

    #[test]
    fn load_of_missing_or_bad_file_is_an_error() {
        assert!(PvdSeries::load(&scratch("missing.pvd")).is_err());
        let p = scratch("bad.pvd");
        std::fs::write(&p, "<DataSet timestep=\"x\" file=\"a\"/>").unwrap();
        assert!(PvdSeries::load(&p).is_err());
    }
}
