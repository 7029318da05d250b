//! Body shapes and how they are filled with material points: a lattice of `n × n` points
//! per cell aligned with the grid, keeping the points that fall inside the shape.

use glam::DVec2;
use serde::{Deserialize, Serialize};

/// The region a body initially occupies.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "snake_case", deny_unknown_fields)]
pub enum Geometry {
    /// A disk (a cylinder in plane strain).
    Disk {
        /// Centre (m).
        centre: [f64; 2],
        /// Radius (m).
        radius: f64,
    },
    /// An axis-aligned rectangle.
    Rectangle {
        /// Lower-left corner (m).
        lo: [f64; 2],
        /// Upper-right corner (m).
        hi: [f64; 2],
    },
    /// A simple polygon, vertices in order (either orientation).
    Polygon {
        /// Vertices (m).
        vertices: Vec<[f64; 2]>,
    },
}

impl Geometry {
    /// True if `p` is inside the shape.
    pub fn contains(&self, p: DVec2) -> bool {
        match self {
            Geometry::Disk { centre, radius } => {
                (p - DVec2::from(*centre)).length_squared() < radius * radius
            }
            Geometry::Rectangle { lo, hi } => {
                p.x > lo[0] && p.x < hi[0] && p.y > lo[1] && p.y < hi[1]
            }
            Geometry::Polygon { vertices } => {
                // Even-odd ray casting towards +x.
                let mut inside = false;
                let n = vertices.len();
                for k in 0..n {
                    let a = DVec2::from(vertices[k]);
                    let b = DVec2::from(vertices[(k + 1) % n]);
                    if (a.y > p.y) != (b.y > p.y) {
                        let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
                        if p.x < x {
                            inside = !inside;
                        }
                    }
                }
                inside
            }
        }
    }

    /// Exact area (m² per unit thickness).
    pub fn area(&self) -> f64 {
        match self {
            Geometry::Disk { radius, .. } => std::f64::consts::PI * radius * radius,
            Geometry::Rectangle { lo, hi } => (hi[0] - lo[0]) * (hi[1] - lo[1]),
            Geometry::Polygon { vertices } => {
                let n = vertices.len();
                let twice: f64 = (0..n)
                    .map(|k| {
                        let (a, b) = (vertices[k], vertices[(k + 1) % n]);
                        a[0] * b[1] - b[0] * a[1]
                    })
                    .sum();
                0.5 * twice.abs()
            }
        }
    }

    /// Bounding box (lo, hi).
    pub fn bounds(&self) -> (DVec2, DVec2) {
        match self {
            Geometry::Disk { centre, radius } => {
                let c = DVec2::from(*centre);
                (c - DVec2::splat(*radius), c + DVec2::splat(*radius))
            }
            Geometry::Rectangle { lo, hi } => (DVec2::from(*lo), DVec2::from(*hi)),
            Geometry::Polygon { vertices } => vertices
                .iter()
                .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), v| {
                    (lo.min(DVec2::from(*v)), hi.max(DVec2::from(*v)))
                }),
        }
    }

    /// Every finite coordinate and positive size; `Err` names what is wrong.
    pub fn validate(&self) -> Result<(), String> {
        let finite = |v: &[f64; 2]| v.iter().all(|x| x.is_finite());
        match self {
            Geometry::Disk { centre, radius } => {
                if !finite(centre) {
                    return Err(format!("centre = {centre:?}: must be finite"));
                }
                if !(radius.is_finite() && *radius > 0.0) {
                    return Err(format!("radius = {radius}: must be a finite number > 0"));
                }
            }
            Geometry::Rectangle { lo, hi } => {
                if !(finite(lo) && finite(hi) && hi[0] > lo[0] && hi[1] > lo[1]) {
                    return Err(format!(
                        "hi = {hi:?}: must be finite and above lo = {lo:?} in x and y"
                    ));
                }
            }
            Geometry::Polygon { vertices } => {
                if vertices.len() < 3 || !vertices.iter().all(finite) {
                    return Err(format!(
                        "vertices = {vertices:?}: need at least 3 finite vertices"
                    ));
                }
                if self.area() <= 0.0 {
                    return Err(format!("vertices = {vertices:?}: the polygon has no area"));
                }
            }
        }
        Ok(())
    }

    /// Material points filling the shape: a lattice of pitch `pitch` whose points sit at
    /// `origin + pitch·(k + ½)`, so with `pitch = h/n` each grid cell holds `n × n`
    /// points at the same places.
    pub fn fill(&self, origin: DVec2, pitch: f64) -> Vec<DVec2> {
        let (lo, hi) = self.bounds();
        let k0 = ((lo - origin) / pitch - 0.5).floor();
        let k1 = ((hi - origin) / pitch - 0.5).ceil();
        let mut out = Vec::new();
        let mut ky = k0.y;
        while ky <= k1.y {
            let mut kx = k0.x;
            while kx <= k1.x {
                let p = origin + pitch * DVec2::new(kx + 0.5, ky + 0.5);
                if self.contains(p) {
                    out.push(p);
                }
                kx += 1.0;
            }
            ky += 1.0;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fills_and_areas() {
        let d = Geometry::Disk {
            centre: [1.0, 1.5],
            radius: 0.5,
        };
        let pts = d.fill(DVec2::ZERO, 0.0625);
        // The lattice count approximates the area only to a few per cent (208 points
        // where π·8² ≈ 201 would be exact): bodies therefore rescale point volumes.
        let a = pts.len() as f64 * 0.0625f64.powi(2);
        assert!((a - d.area()).abs() < 0.05 * d.area(), "{a}");
        let r = Geometry::Rectangle {
            lo: [0.0, 0.0],
            hi: [1.0, 0.5],
        };
        assert_eq!(r.fill(DVec2::ZERO, 0.125).len(), 32);
        let tri = Geometry::Polygon {
            vertices: vec![[0.0, 0.0], [2.0, 0.0], [0.0, 1.0]],
        };
        assert!((tri.area() - 1.0).abs() < 1e-12);
        assert!(tri.contains(DVec2::new(0.5, 0.2)) && !tri.contains(DVec2::new(1.5, 0.9)));
        assert!(tri.validate().is_ok());
        assert!(Geometry::Disk {
            centre: [0.0, 0.0],
            radius: -1.0
        }
        .validate()
        .is_err());
    }
}
