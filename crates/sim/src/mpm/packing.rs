//! A packing file (`grains pack`) turned into MPM bodies (`[[packing]]`): one free body
//! per disk, named by a prefix and its place in the file; the lining disks (the first
//! ones, on the packing's walls) either added to two rigid union bodies (the boundaries
//! they are fixed to) or kept as free grains. The expanded scenario is what everything
//! after reads: a binder with `minus = ["*"]` is cut around every grain.

use super::scenario::{BodySpec, Scenario};
use glam::DVec2;
use grains_core::input::{InputError, Shown};
use grains_mpm::Geometry;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// One `[[packing]]`.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PackingSpec {
    /// The packing file (`x y r` lines, `# lining = N` header), relative to the scenario.
    pub file: String,
    /// The grains' material.
    pub material: String,
    /// Grain body names: the prefix and the disk's number (from 0, lining excluded).
    #[serde(default = "default_prefix")]
    pub prefix: String,
    /// Swap x and y: a packing periodic in x becomes a cell periodic in y.
    #[serde(default)]
    pub swap_xy: bool,
    /// Every radius is multiplied by this, in (0, 1] (< 1 opens gaps for a binder).
    #[serde(default = "one")]
    pub radius_scale: f64,
    /// The lining disks go to these two rigid bodies, whose shapes must be unions: those
    /// nearer the low x edge to the first, the rest to the second. Without, they are
    /// free grains like the others.
    #[serde(default)]
    pub lining: Option<[String; 2]>,
}

fn default_prefix() -> String {
    "grain".into()
}
fn one() -> f64 {
    1.0
}

/// `s` read from `src` with its packings expanded; errors name the file.
pub fn expanded(s: &Scenario, src: &crate::Source) -> Result<Scenario, String> {
    expand(s, &src.base).map_err(|e| format!("{}: {e}", src.origin))
}

/// `s` with every `[[packing]]` replaced by its bodies (files read from `base`).
pub fn expand(s: &Scenario, base: &Path) -> Result<Scenario, InputError> {
    if s.packings.is_empty() {
        return Ok(s.clone());
    }
    let mut out = s.clone();
    out.packings.clear();
    let g = &s.grid;
    for (k, p) in s.packings.iter().enumerate() {
        let key = format!("packing[{k}]");
        if !(p.radius_scale > 0.0 && p.radius_scale <= 1.0) {
            return Err(InputError::new(
                format!("{key}.radius_scale"),
                p.radius_scale,
                "must be in (0, 1]",
            ));
        }
        let path = base.join(&p.file);
        let sample = grains_analysis::sample::load(&path).map_err(|e| {
            InputError::new(
                format!("{key}.file"),
                format!("\"{}\"", p.file),
                format!("cannot be used as a packing: {e}"),
            )
        })?;
        let disks: Vec<(DVec2, f64)> = sample
            .pos
            .iter()
            .zip(&sample.radius)
            .map(|(x, r)| {
                let x = if p.swap_xy { DVec2::new(x.y, x.x) } else { *x };
                (x, r * p.radius_scale)
            })
            .collect();
        // Every grain must lie in the grid: wholly along a walled axis, by its centre
        // along a periodic one (it wraps).
        for (i, (x, r)) in disks.iter().enumerate() {
            let inside = |axis: usize, v: f64, periodic: bool| {
                let (lo, hi) = (g.lo[axis], g.hi[axis]);
                if periodic {
                    v >= lo && v < hi
                } else {
                    v - r >= lo && v + r <= hi
                }
            };
            if !(inside(0, x.x, false) && inside(1, x.y, g.periodic_y.is_some())) {
                return Err(InputError::new(
                    format!("{key}.file"),
                    format!(
                        "\"{}\": disk {i} at ({}, {}) of radius {}",
                        p.file,
                        x.x.shown(),
                        x.y.shown(),
                        r.shown()
                    ),
                    format!(
                        "every grain must lie inside the grid [{:?}, {:?}]{}",
                        g.lo,
                        g.hi,
                        if p.swap_xy { " (after swap_xy)" } else { "" }
                    ),
                ));
            }
        }
        let (lining, grains) = disks.split_at(sample.lining);
        let disk = |(x, r): &(DVec2, f64)| Geometry::Disk {
            centre: x.to_array(),
            radius: *r,
        };
        match &p.lining {
            Some(names) => {
                let middle = 0.5 * (g.lo[0] + g.hi[0]);
                for (side, name) in names.iter().enumerate() {
                    let body = out.bodies.iter_mut().find(|b| &b.name == name);
                    let Some(BodySpec {
                        geometry: Geometry::Union { parts },
                        rigid: true,
                        ..
                    }) = body
                    else {
                        return Err(InputError::new(
                            format!("{key}.lining[{side}]"),
                            format!("\"{name}\""),
                            "must name a rigid body (rigid = true) whose geometry is a union",
                        ));
                    };
                    parts.extend(
                        lining
                            .iter()
                            .filter(|(x, _)| (x.x >= middle) == (side == 1))
                            .map(disk),
                    );
                }
            }
            None => out.bodies.extend(
                lining
                    .iter()
                    .enumerate()
                    .map(|(i, d)| grain(format!("{}lining{i}", p.prefix), &p.material, disk(d))),
            ),
        }
        out.bodies.extend(
            grains
                .iter()
                .enumerate()
                .map(|(i, d)| grain(format!("{}{i}", p.prefix), &p.material, disk(d))),
        );
    }
    Ok(out)
}

/// A free grain at rest.
fn grain(name: String, material: &str, geometry: Geometry) -> BodySpec {
    BodySpec {
        name,
        material: material.into(),
        geometry,
        velocity: [0.0, 0.0],
        velocity_gradient: None,
        rigid: false,
        velocity_table: None,
        temperature: None,
        minus: Vec::new(),
    }
}
