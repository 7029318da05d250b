//! Contacts, coordination and the contact-normal fabric.
//!
//! A pair is in contact when its gap `|c_i − c_j| − r_i − r_j` is at most a threshold:
//! `10⁻³ d0` for a generated packing, `0` (any overlap, i.e. a positive elastic normal
//! force) for a DEM frame. Only particle–particle contacts count; wall contacts do not.

use crate::grid::CellGrid;
use crate::region::Region;
use glam::{DMat2, DVec2};
use rayon::prelude::*;

/// The contact network of a packing.
#[derive(Clone, Debug, Default)]
pub struct Contacts {
    /// Each contact once, as `(i, j)` with `i < j`.
    pub pairs: Vec<(u32, u32)>,
    /// Unit normal from `i` to `j` of each pair.
    pub normals: Vec<DVec2>,
    /// Contacts per particle.
    pub count: Vec<u32>,
}

/// Finds every pair with gap ≤ `max_gap`. `grid` must have cells at least as large
/// as the largest diameter plus `max_gap`.
pub fn find(
    pos: &[DVec2],
    radius: &[f64],
    region: &Region,
    grid: &CellGrid,
    max_gap: f64,
) -> Contacts {
    let per: Vec<Vec<(u32, DVec2)>> = (0..pos.len())
        .into_par_iter()
        .with_min_len(1024)
        .map(|i| {
            let mut out = Vec::new();
            grid.for_each_near(pos[i], 1, |j| {
                if (j as usize) > i {
                    let d = region.delta(pos[i], pos[j as usize]);
                    let dist = d.length();
                    if dist - radius[i] - radius[j as usize] <= max_gap && dist > 0.0 {
                        out.push((j, d / dist));
                    }
                }
            });
            out.sort_by_key(|e| e.0);
            out
        })
        .collect();
    let mut c = Contacts {
        count: vec![0; pos.len()],
        ..Default::default()
    };
    for (i, list) in per.into_iter().enumerate() {
        for (j, n) in list {
            c.pairs.push((i as u32, j));
            c.normals.push(n);
            c.count[i] += 1;
            c.count[j as usize] += 1;
        }
    }
    c
}

/// The fabric tensor F = (1/N_c) Σ n⊗n of a set of contact normals and its anisotropy.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fabric {
    /// F.
    pub tensor: DMat2,
    /// Larger principal value F_I.
    pub major: f64,
    /// Smaller principal value F_II.
    pub minor: f64,
    /// Direction of the major principal axis (rad, in [0, π)).
    pub major_angle: f64,
    /// Contacts counted.
    pub count: usize,
}

impl Fabric {
    /// Anisotropy a = F_I − F_II: 0 for isotropic normals, 1 when all are parallel.
    pub fn anisotropy(&self) -> f64 {
        self.major - self.minor
    }
}

/// Fabric of the normals selected by `keep`.
pub fn fabric(normals: &[DVec2], keep: impl Fn(usize) -> bool) -> Fabric {
    let (mut xx, mut xy, mut yy, mut n) = (0.0, 0.0, 0.0, 0usize);
    for (k, v) in normals.iter().enumerate() {
        if keep(k) {
            xx += v.x * v.x;
            xy += v.x * v.y;
            yy += v.y * v.y;
            n += 1;
        }
    }
    if n == 0 {
        return Fabric {
            tensor: DMat2::ZERO,
            major: f64::NAN,
            minor: f64::NAN,
            major_angle: f64::NAN,
            count: 0,
        };
    }
    let (xx, xy, yy) = (xx / n as f64, xy / n as f64, yy / n as f64);
    let mean = 0.5 * (xx + yy);
    let rad = (0.25 * (xx - yy) * (xx - yy) + xy * xy).sqrt();
    let angle = (0.5 * (2.0 * xy).atan2(xx - yy)).rem_euclid(std::f64::consts::PI);
    Fabric {
        tensor: DMat2::from_cols(DVec2::new(xx, xy), DVec2::new(xy, yy)),
        major: mean + rad,
        minor: mean - rad,
        major_angle: angle,
        count: n,
    }
}

/// Histogram of contact-normal directions over `bins` equal sectors of [0, 2π), each
/// contact counted in both directions (n and −n), normalised to a probability density
/// in 1/rad. This is the rose diagram's data.
pub fn rose(normals: &[DVec2], keep: impl Fn(usize) -> bool, bins: usize) -> Vec<f64> {
    let bins = bins.max(1);
    let mut h = vec![0.0; bins];
    let width = std::f64::consts::TAU / bins as f64;
    let mut total = 0.0;
    for (k, v) in normals.iter().enumerate() {
        if !keep(k) {
            continue;
        }
        for n in [*v, -*v] {
            let a = n.y.atan2(n.x).rem_euclid(std::f64::consts::TAU);
            h[((a / width) as usize).min(bins - 1)] += 1.0;
            total += 1.0;
        }
    }
    if total > 0.0 {
        for x in &mut h {
            *x /= total * width;
        }
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fabric_limits() {
        let same = vec![DVec2::new(0.6, 0.8); 10];
        let f = fabric(&same, |_| true);
        assert!((f.anisotropy() - 1.0).abs() < 1e-12);
        assert!((f.major_angle - 0.8f64.atan2(0.6)).abs() < 1e-12);
        let iso: Vec<DVec2> = (0..12)
            .map(|k| DVec2::from_angle(k as f64 * std::f64::consts::PI / 6.0))
            .collect();
        let f = fabric(&iso, |_| true);
        assert!(f.anisotropy().abs() < 1e-12 && (f.major - 0.5).abs() < 1e-12);
        let h = rose(&iso, |_| true, 12);
        let integral: f64 = h.iter().sum::<f64>() * std::f64::consts::TAU / 12.0;
        assert!((integral - 1.0).abs() < 1e-12);
    }

    #[test]
    fn finds_touching_pairs_only() {
        let pos = vec![DVec2::ZERO, DVec2::new(2.0, 0.0), DVec2::new(4.1, 0.0)];
        let r = vec![1.0; 3];
        let region = Region::bounding_box(&pos, &r);
        let (lo, hi) = region.bounds();
        let g = CellGrid::build(&pos, lo, hi, 2.2, None);
        let c = find(&pos, &r, &region, &g, 1e-3);
        assert_eq!(c.pairs, vec![(0, 1)]);
        assert_eq!(c.count, vec![1, 1, 0]);
        let c = find(&pos, &r, &region, &g, 0.2);
        assert_eq!(c.pairs.len(), 2);
    }
}
