//! Reader for LAMMPS data files of `atom_style sphere` (as `write_data` writes them), so
//! users can start grains from the beds they built with LAMMPS.
//!
//! What a granular run needs is read, in 2D or 3D: the box, and per atom its id, type,
//! diameter, density and position (Atoms section, `id type diameter density x y z`
//! with optional image flags), plus velocities and angular velocities if a Velocities
//! section is present (`id vx vy vz wx wy wz`).

use std::path::Path;

/// One atom of a data file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Atom {
    /// LAMMPS atom id.
    pub id: u64,
    /// Atom type.
    pub kind: u32,
    /// Diameter.
    pub diameter: f64,
    /// Density as written (LAMMPS writes a sphere-equivalent density even in 2D).
    pub density: f64,
    /// Position.
    pub pos: [f64; 3],
    /// Velocity (zero if the file has no Velocities section).
    pub vel: [f64; 3],
    /// Angular velocity.
    pub omega: [f64; 3],
}

/// The contents of a data file that grains uses.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LammpsData {
    /// Box lower bounds (xlo, ylo, zlo).
    pub lo: [f64; 3],
    /// Box upper bounds.
    pub hi: [f64; 3],
    /// Atoms, sorted by id.
    pub atoms: Vec<Atom>,
}

/// A data file that could not be read, with the line at fault.
#[derive(Debug, thiserror::Error)]
pub enum DataError {
    /// The file could not be opened.
    #[error("{0}: cannot read: {1}")]
    Io(String, std::io::Error),
    /// A line did not parse.
    #[error("{file}: line {line}: {what}")]
    Parse {
        /// File name.
        file: String,
        /// 1-based line number.
        line: usize,
        /// What was wrong.
        what: String,
    },
}

impl LammpsData {
    /// The file's dimension. A data file does not state it; LAMMPS writes a 2D system
    /// with every atom at z = 0, so any atom off that plane makes the file 3D.
    pub fn dimension(&self) -> usize {
        if self.atoms.iter().all(|a| a.pos[2] == 0.0) {
            2
        } else {
            3
        }
    }

    /// `Ok` when the file is of dimension `dim`; otherwise one line naming the file,
    /// the value that shows its dimension and what the run needs.
    pub fn require_dimension(&self, dim: usize, name: &str) -> Result<(), String> {
        match (self.dimension(), dim) {
            (a, b) if a == b => Ok(()),
            (2, _) => Err(format!(
                "{name}: every atom at z = 0, a 2D data file: a {dim}D run needs a {dim}D one (atom_style sphere with dimension {dim})"
            )),
            _ => {
                let a = self.atoms.iter().find(|a| a.pos[2] != 0.0);
                let (id, z) = a.map_or((0, 0.0), |a| (a.id, a.pos[2]));
                Err(format!(
                    "{name}: atom {id} at z = {z}, a 3D data file: a {dim}D run needs a {dim}D one (every atom at z = 0)"
                ))
            }
        }
    }
}

/// Reads a data file.
pub fn read(path: &Path) -> Result<LammpsData, DataError> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| DataError::Io(name.clone(), e))?;
    parse(&text, &name)
}

/// Parses data-file text; `name` is used in errors.
pub fn parse(text: &str, name: &str) -> Result<LammpsData, DataError> {
    let bad = |line: usize, what: String| DataError::Parse {
        file: name.to_string(),
        line: line + 1,
        what,
    };
    let mut data = LammpsData::default();
    let mut declared: Option<usize> = None;
    let mut section = "";
    let mut velocities: Vec<(u64, [f64; 6])> = Vec::new();
    for (ln, raw) in text.lines().enumerate() {
        if ln == 0 {
            continue; // the first line is a free-form title
        }
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let words: Vec<&str> = line.split_whitespace().collect();
        if words[0]
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_alphabetic())
        {
            section = match words[0] {
                "Atoms" => "atoms",
                "Velocities" => "velocities",
                // Sections grains does not need are skipped.
                w if w.chars().next().is_some_and(char::is_uppercase) => "skip",
                _ => return Err(bad(ln, format!("unexpected keyword line {line:?}"))),
            };
            continue;
        }
        let nums = || -> Result<Vec<f64>, DataError> {
            words
                .iter()
                .map(|w| w.parse::<f64>())
                .collect::<Result<_, _>>()
                .map_err(|_| bad(ln, format!("expected numbers, found {line:?}")))
        };
        match section {
            "" => {
                // Header: counts and box bounds.
                let tail = &words[words.len().saturating_sub(2)..];
                if words.len() == 2 && words[1] == "atoms" {
                    declared = Some(
                        words[0]
                            .parse()
                            .map_err(|_| bad(ln, "bad atom count".into()))?,
                    );
                } else if words.len() == 4 && tail[1].len() == 3 && tail[1].ends_with("hi") {
                    let axis = match tail[0] {
                        "xlo" => 0,
                        "ylo" => 1,
                        "zlo" => 2,
                        _ => return Err(bad(ln, format!("unknown bounds {line:?}"))),
                    };
                    let v = words[..2]
                        .iter()
                        .map(|w| w.parse::<f64>())
                        .collect::<Result<Vec<_>, _>>()
                        .map_err(|_| bad(ln, "bad box bounds".into()))?;
                    data.lo[axis] = v[0];
                    data.hi[axis] = v[1];
                }
            }
            "atoms" => {
                let v = nums()?;
                if v.len() != 7 && v.len() != 10 {
                    return Err(bad(
                        ln,
                        format!("an atom_style sphere line has 7 or 10 columns (id type diameter density x y z [ix iy iz]), found {}", v.len()),
                    ));
                }
                let image = if v.len() == 10 {
                    [v[7], v[8], v[9]]
                } else {
                    [0.0; 3]
                };
                let mut pos = [v[4], v[5], v[6]];
                for a in 0..3 {
                    pos[a] += image[a] * (data.hi[a] - data.lo[a]);
                }
                data.atoms.push(Atom {
                    id: v[0] as u64,
                    kind: v[1] as u32,
                    diameter: v[2],
                    density: v[3],
                    pos,
                    vel: [0.0; 3],
                    omega: [0.0; 3],
                });
            }
            "velocities" => {
                let v = nums()?;
                if v.len() != 7 {
                    return Err(bad(ln, format!("a sphere Velocities line has 7 columns (id vx vy vz wx wy wz), found {}", v.len())));
                }
                velocities.push((v[0] as u64, [v[1], v[2], v[3], v[4], v[5], v[6]]));
            }
            _ => {}
        }
    }
    data.atoms.sort_by_key(|a| a.id);
    if let Some(n) = declared {
        if n != data.atoms.len() {
            return Err(bad(
                0,
                format!(
                    "header declares {n} atoms, the Atoms section has {}",
                    data.atoms.len()
                ),
            ));
        }
    }
    for (id, v) in velocities {
        let Ok(k) = data.atoms.binary_search_by_key(&id, |a| a.id) else {
            return Err(bad(
                0,
                format!("Velocities names atom {id}, which is not in Atoms"),
            ));
        };
        data.atoms[k].vel = [v[0], v[1], v[2]];
        data.atoms[k].omega = [v[3], v[4], v[5]];
    }
    Ok(data)
}

/// The atom count a data file's header declares (the `N atoms` line), read without the
/// rest of the file; `None` if the file cannot be read or declares none.
pub fn atom_count(path: &Path) -> Option<u64> {
    use std::io::BufRead;
    let f = std::fs::File::open(path).ok()?;
    for line in std::io::BufReader::new(f).lines().take(100) {
        let line = line.ok()?;
        let words: Vec<&str> = line.split_whitespace().collect();
        if words.len() == 2 && words[1] == "atoms" {
            return words[0].parse().ok();
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    const SAMPLE: &str = "LAMMPS data file via write_data\n\n2 atoms\n1 atom types\n\n0 10 xlo xhi\n-0.5 5 ylo yhi\n-0.5 0.5 zlo zhi\n\nAtoms # sphere\n\n2 1 0.9 1.5 3.0 1.0 0.0 0 0 0\n1 1 0.95 1.5 1.0 1.0 0.0 1 0 0\n\nVelocities\n\n1 0.1 0.2 0 0 0 0.5\n2 0 0 0 0 0 0\n";

    #[test]
    fn reads_box_atoms_and_velocities() {
        let d = parse(SAMPLE, "sample").unwrap();
        assert_eq!(d.lo, [0.0, -0.5, -0.5]);
        assert_eq!(d.hi, [10.0, 5.0, 0.5]);
        assert_eq!(d.atoms.len(), 2);
        assert_eq!(d.atoms[0].id, 1);
        assert_eq!(d.atoms[0].pos, [11.0, 1.0, 0.0]);
        assert_eq!(d.atoms[0].vel, [0.1, 0.2, 0.0]);
        assert_eq!(d.atoms[0].omega[2], 0.5);
    }

    #[test]
    fn tells_2d_from_3d() {
        let d2 = parse(SAMPLE, "sample").unwrap();
        assert_eq!(d2.dimension(), 2);
        assert!(d2.require_dimension(2, "f").is_ok());
        let e = d2.require_dimension(3, "f").unwrap_err();
        assert!(e.contains("z = 0") && e.contains("3D run"), "{e}");
        let d3 = parse(
            &SAMPLE.replace("3.0 1.0 0.0 0 0 0", "3.0 1.0 2.5 0 0 0"),
            "s",
        )
        .unwrap();
        assert_eq!(d3.dimension(), 3);
        assert_eq!(d3.atoms[1].pos, [3.0, 1.0, 2.5]);
        let e = d3.require_dimension(2, "f").unwrap_err();
        assert!(e.contains("atom 2 at z = 2.5"), "{e}");
    }

    #[test]
    fn bad_lines_name_the_line() {
        let e = parse(&SAMPLE.replace("2 1 0.9 1.5 3.0", "2 1 zz 1.5 3.0"), "f").unwrap_err();
        assert!(e.to_string().contains("line 12"), "{e}");
        let e = parse(&SAMPLE.replace("2 atoms", "3 atoms"), "f").unwrap_err();
        assert!(e.to_string().contains("declares 3"), "{e}");
    }
}
