//! The sphere packing spec (`dim = 3`): a box or a z-cylinder filled with jammed
//! frictionless spheres by [`crate::spheres::jam`], and the packing file it writes
//! (`x y z r` per line, SI), which a 3D scenario loads with `source = "file"`.

use crate::spec::CheckSpec;
use crate::spheres::{Container, SpherePacking};
use grains_core::input::{positive, InputError};
use serde::{Deserialize, Serialize};
use std::fmt::Write;

/// Most spheres a spec may ask for: the packer's minimisations are all-pairs within
/// cells, seconds for 10³ spheres and minutes for 10⁴.
pub const MAX_SPHERES: usize = 20_000;

/// A whole sphere packing spec.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereSpec {
    /// Name; the default output directory is `runs/<name>`.
    pub name: String,
    /// Free text.
    #[serde(default)]
    pub description: String,
    /// 3.
    pub dim: u32,
    /// Seed of the spheres' starting places.
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// The container's shape.
    pub domain: ContainerSpec,
    /// The spheres.
    pub sizes: SphereSizes,
    /// Checks of summary figures (exit 2 when one fails).
    #[serde(rename = "check", default)]
    pub checks: Vec<CheckSpec>,
}

fn default_seed() -> u64 {
    1
}

fn default_ratio() -> f64 {
    1.0
}

/// `[domain]`: the container's shape. Its size is then set to hold the spheres at
/// jamming (only the proportions given are kept); summary.json gives the size reached.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "snake_case", deny_unknown_fields)]
pub enum ContainerSpec {
    /// The box `[0, size]`, walled on every side.
    Box {
        /// Edge lengths (m).
        size: [f64; 3],
    },
    /// The cylinder about the z axis through (0, 0) from z = 0 to `height`, walled at
    /// both ends.
    Cylinder {
        /// Radius (m).
        radius: f64,
        /// Height (m).
        height: f64,
    },
}

/// `[sizes]`: a 50:50 mixture of diameters `diameter` and `ratio` × `diameter`.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereSizes {
    /// Number of spheres.
    pub count: usize,
    /// Diameter of the first half (m).
    pub diameter: f64,
    /// Diameter of the second half over the first's (1: one size).
    #[serde(default = "default_ratio")]
    pub ratio: f64,
}

impl SphereSpec {
    /// Checks every value, naming the first bad one.
    pub fn validate(&self) -> Result<Container, InputError> {
        if self.dim != 3 {
            return Err(InputError::new("dim", self.dim, "3 (spheres)"));
        }
        let n = self.sizes.count;
        if !(2..=MAX_SPHERES).contains(&n) {
            return Err(InputError::new(
                "sizes.count",
                n,
                format!("from 2 to {MAX_SPHERES}"),
            ));
        }
        positive("sizes.diameter", self.sizes.diameter)?;
        let ratio = self.sizes.ratio;
        if !(1.0..=3.0).contains(&ratio) {
            return Err(InputError::new("sizes.ratio", ratio, "from 1 to 3"));
        }
        for c in &self.checks {
            if c.at_least.is_some() == c.at_most.is_some() {
                return Err(InputError::new(
                    format!("check \"{}\"", c.figure),
                    "",
                    "exactly one of at_least and at_most",
                ));
            }
        }
        Ok(match self.domain {
            ContainerSpec::Box { size } => {
                for (a, x) in ["x", "y", "z"].iter().zip(size) {
                    positive(&format!("domain.size.{a}"), x)?;
                }
                Container::Box { size }
            }
            ContainerSpec::Cylinder { radius, height } => {
                positive("domain.radius", radius)?;
                positive("domain.height", height)?;
                Container::Cylinder { radius, height }
            }
        })
    }
}

/// The packing file: `#` header lines, then one line `x y z r` per sphere (SI units,
/// shortest round-trip numbers, so reading it gives back the packed values).
pub fn packing_text(spec: &SphereSpec, p: &SpherePacking) -> String {
    let mut s = String::with_capacity(p.pos.len() * 80 + 512);
    let _ = writeln!(s, "# grains pack (spheres): {}", spec.name);
    crate::output::provenance(&mut s, &spec.description, spec.seed);
    let _ = writeln!(s, "# dim = 3");
    let container = match p.container {
        Container::Box { size } => format!("box size={size:?}"),
        Container::Cylinder { radius, height } => {
            format!("cylinder radius={radius:e} height={height:e}")
        }
    };
    let _ = writeln!(s, "# container = {container}");
    let _ = writeln!(
        s,
        "# realised = phi_bulk={:e} phi_interior={:e} coordination={:e}",
        p.phi_bulk, p.phi_interior, p.coordination
    );
    let _ = writeln!(s, "# columns: x y z r (m)");
    for (c, r) in p.pos.iter().zip(&p.radius) {
        let _ = writeln!(s, "{:e} {:e} {:e} {:e}", c.x, c.y, c.z, r);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(text: &str) -> SphereSpec {
        toml::from_str(text).unwrap()
    }

    const SPEC: &str = "name = \"p\"\ndim = 3\n[domain]\nshape = \"cylinder\"\nradius = 0.01\nheight = 0.02\n[sizes]\ncount = 40\ndiameter = 0.002\n";

    #[test]
    fn bad_values_are_named() {
        let bad = [
            ("count = 40", "count = 1", "sizes.count"),
            ("diameter = 0.002", "diameter = -0.002", "sizes.diameter"),
            ("radius = 0.01", "radius = 0.0", "domain.radius"),
            ("dim = 3", "dim = 2", "dim"),
        ];
        for (from, to, key) in bad {
            let e = spec(&SPEC.replace(from, to)).validate().unwrap_err();
            assert!(e.to_string().contains(key), "{e}");
        }
        let e = spec(&format!("{SPEC}ratio = 4.0\n"))
            .validate()
            .unwrap_err();
        assert!(e.to_string().contains("sizes.ratio"), "{e}");
    }

    #[test]
    fn the_file_reads_back_exactly() {
        let s = spec(SPEC);
        let c = s.validate().unwrap();
        let p = crate::spheres::jam(40, s.sizes.diameter, 1.0, c, 2);
        let text = packing_text(&s, &p);
        let rows: Vec<Vec<f64>> = text
            .lines()
            .filter(|l| !l.starts_with('#'))
            .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
            .collect();
        assert_eq!(rows.len(), 40);
        assert_eq!(
            rows[7],
            vec![p.pos[7].x, p.pos[7].y, p.pos[7].z, p.radius[7]]
        );
    }
}
