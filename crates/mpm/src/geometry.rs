//! Body shapes and how they are filled with material points: a lattice of `n × n` points
//! per cell aligned with the grid, keeping the points that fall inside the shape. Shapes
//! that share the lattice never share a point, so a region minus other bodies (a binder
//! around grains) is filled exactly where they are not.

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
    /// A ring: the points at distance r from the centre with inner ≤ r < outer (a disk of
    /// radius `inner` at the same centre holds exactly the rest).
    Annulus {
        /// Centre (m).
        centre: [f64; 2],
        /// Inner radius (m), ≥ 0.
        inner: f64,
        /// Outer radius (m), > inner.
        outer: f64,
    },
    /// `base` without the shapes in `minus` (e.g. the binder: a box minus the grains).
    Difference {
        /// The region filled.
        base: Box<Geometry>,
        /// The holes (other bodies' shapes).
        minus: Vec<Geometry>,
    },
    /// Several shapes as one (e.g. a boundary with the grains fixed to it); they may
    /// overlap.
    Union {
        /// The shapes.
        parts: Vec<Geometry>,
    },
}

/// Sample points per axis of the numerical area of shapes without a closed form.
const AREA_SAMPLES: usize = 1024;

/// Area of the part of `lo..hi` where `inside` holds, by the midpoint rule on a
/// [`AREA_SAMPLES`]² lattice (relative error ~ 1/[`AREA_SAMPLES`] of the boundary's share).
fn sampled_area((lo, hi): (DVec2, DVec2), inside: impl Fn(DVec2) -> bool) -> f64 {
    let d = (hi - lo) / AREA_SAMPLES as f64;
    let mut n = 0usize;
    for j in 0..AREA_SAMPLES {
        for i in 0..AREA_SAMPLES {
            n += inside(lo + d * DVec2::new(i as f64 + 0.5, j as f64 + 0.5)) as usize;
        }
    }
    n as f64 * d.x * d.y
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
            Geometry::Annulus {
                centre,
                inner,
                outer,
            } => {
                let r2 = (p - DVec2::from(*centre)).length_squared();
                r2 >= inner * inner && r2 < outer * outer
            }
            Geometry::Difference { base, minus } => {
                base.contains(p) && !minus.iter().any(|m| m.contains(p))
            }
            Geometry::Union { parts } => parts.iter().any(|g| g.contains(p)),
        }
    }

    /// The same shape moved by `d`.
    pub fn translated(&self, d: DVec2) -> Geometry {
        let m = |v: &[f64; 2]| (DVec2::from(*v) + d).to_array();
        match self {
            Geometry::Disk { centre, radius } => Geometry::Disk {
                centre: m(centre),
                radius: *radius,
            },
            Geometry::Rectangle { lo, hi } => Geometry::Rectangle {
                lo: m(lo),
                hi: m(hi),
            },
            Geometry::Polygon { vertices } => Geometry::Polygon {
                vertices: vertices.iter().map(m).collect(),
            },
            Geometry::Annulus {
                centre,
                inner,
                outer,
            } => Geometry::Annulus {
                centre: m(centre),
                inner: *inner,
                outer: *outer,
            },
            Geometry::Difference { base, minus } => Geometry::Difference {
                base: Box::new(base.translated(d)),
                minus: minus.iter().map(|g| g.translated(d)).collect(),
            },
            Geometry::Union { parts } => Geometry::Union {
                parts: parts.iter().map(|g| g.translated(d)).collect(),
            },
        }
    }

    /// `self` without the shapes `others`.
    pub fn minus(self, others: Vec<Geometry>) -> Geometry {
        Geometry::Difference {
            base: Box::new(self),
            minus: others,
        }
    }

    /// True if the convex shape `self` surely contains all of `other` (its bounding box
    /// is inside); false when unsure.
    fn surely_contains(&self, other: &Geometry) -> bool {
        let (lo, hi) = other.bounds();
        let convex = matches!(self, Geometry::Disk { .. } | Geometry::Rectangle { .. });
        let corners = [lo, hi, DVec2::new(lo.x, hi.y), DVec2::new(hi.x, lo.y)];
        let inner_disk = match (self, other) {
            (
                Geometry::Disk { centre, radius },
                Geometry::Disk {
                    centre: c,
                    radius: r,
                },
            ) => (DVec2::from(*centre) - DVec2::from(*c)).length() + r <= *radius,
            _ => false,
        };
        inner_disk || (convex && corners.iter().all(|c| self.contains(*c)))
    }

    /// True if the two shapes surely do not overlap; false when unsure.
    fn surely_apart(&self, other: &Geometry) -> bool {
        if let (
            Geometry::Disk { centre, radius },
            Geometry::Disk {
                centre: c,
                radius: r,
            },
        ) = (self, other)
        {
            return (DVec2::from(*centre) - DVec2::from(*c)).length() >= radius + r;
        }
        let ((a0, a1), (b0, b1)) = (self.bounds(), other.bounds());
        a1.x <= b0.x || b1.x <= a0.x || a1.y <= b0.y || b1.y <= a0.y
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
            Geometry::Annulus { inner, outer, .. } => {
                std::f64::consts::PI * (outer * outer - inner * inner)
            }
            Geometry::Difference { base, minus } => {
                let apart = minus
                    .iter()
                    .enumerate()
                    .all(|(k, a)| minus[k + 1..].iter().all(|b| a.surely_apart(b)));
                if !apart {
                    return sampled_area(self.bounds(), |p| self.contains(p));
                }
                // Disjoint holes: each removes its overlap with the base, exactly when it
                // lies wholly inside or wholly outside.
                let removed: f64 = minus
                    .iter()
                    .map(|m| {
                        if base.surely_contains(m) {
                            m.area()
                        } else if base.surely_apart(m) {
                            0.0
                        } else {
                            sampled_area(m.bounds(), |p| m.contains(p) && base.contains(p))
                        }
                    })
                    .sum();
                base.area() - removed
            }
            Geometry::Union { parts } => {
                let apart = parts
                    .iter()
                    .enumerate()
                    .all(|(k, a)| parts[k + 1..].iter().all(|b| a.surely_apart(b)));
                if apart {
                    parts.iter().map(Geometry::area).sum()
                } else {
                    sampled_area(self.bounds(), |p| self.contains(p))
                }
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
            Geometry::Annulus { centre, outer, .. } => {
                let c = DVec2::from(*centre);
                (c - DVec2::splat(*outer), c + DVec2::splat(*outer))
            }
            Geometry::Difference { base, .. } => base.bounds(),
            Geometry::Union { parts } => parts.iter().map(Geometry::bounds).fold(
                (DVec2::INFINITY, DVec2::NEG_INFINITY),
                |(lo, hi), (a, b)| (lo.min(a), hi.max(b)),
            ),
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
            Geometry::Annulus {
                centre,
                inner,
                outer,
            } => {
                if !finite(centre) {
                    return Err(format!("centre = {centre:?}: must be finite"));
                }
                if !(inner.is_finite() && *inner >= 0.0) {
                    return Err(format!("inner = {inner}: must be a finite number >= 0"));
                }
                if !(outer.is_finite() && outer > inner) {
                    return Err(format!(
                        "outer = {outer}: must be finite and greater than inner = {inner}"
                    ));
                }
            }
            Geometry::Difference { base, minus } => {
                base.validate().map_err(|e| format!("base.{e}"))?;
                for (k, m) in minus.iter().enumerate() {
                    m.validate().map_err(|e| format!("minus[{k}].{e}"))?;
                }
                if self.area() <= 0.0 {
                    return Err("minus: the holes cover the whole base".into());
                }
            }
            Geometry::Union { parts } => {
                if parts.is_empty() {
                    return Err("parts = []: need at least one shape".into());
                }
                for (k, g) in parts.iter().enumerate() {
                    g.validate().map_err(|e| format!("parts[{k}].{e}"))?;
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

    #[test]
    fn annulus_and_disk_share_no_point_and_leave_no_gap() {
        let (c, a, b) = ([1.0, 1.0], 0.4, 0.8);
        let disk = Geometry::Disk {
            centre: c,
            radius: a,
        };
        let ring = Geometry::Annulus {
            centre: c,
            inner: a,
            outer: b,
        };
        let whole = Geometry::Disk {
            centre: c,
            radius: b,
        };
        let pitch = 0.025;
        let (d, r, w) = (
            disk.fill(DVec2::ZERO, pitch),
            ring.fill(DVec2::ZERO, pitch),
            whole.fill(DVec2::ZERO, pitch),
        );
        assert_eq!(d.len() + r.len(), w.len());
        assert!(d.iter().all(|p| !ring.contains(*p)));
        assert!((ring.area() + disk.area() - whole.area()).abs() < 1e-12);
        assert!(ring.validate().is_ok());
        let bad = Geometry::Annulus {
            centre: c,
            inner: 0.9,
            outer: 0.8,
        };
        assert!(bad.validate().unwrap_err().contains("outer = 0.8"));
    }

    #[test]
    fn region_minus_bodies_fills_the_complement() {
        let grains = vec![
            Geometry::Disk {
                centre: [0.5, 0.5],
                radius: 0.3,
            },
            Geometry::Disk {
                centre: [1.2, 0.5],
                radius: 0.3,
            },
            // Cut by the box's edge.
            Geometry::Disk {
                centre: [2.0, 0.5],
                radius: 0.3,
            },
        ];
        let bx = Geometry::Rectangle {
            lo: [0.0, 0.0],
            hi: [2.0, 1.0],
        };
        let binder = bx.clone().minus(grains.clone());
        let pitch = 0.02;
        let b = binder.fill(DVec2::ZERO, pitch);
        let g: usize = grains
            .iter()
            .map(|d| {
                d.fill(DVec2::ZERO, pitch)
                    .iter()
                    .filter(|p| bx.contains(**p))
                    .count()
            })
            .sum();
        assert_eq!(b.len() + g, bx.fill(DVec2::ZERO, pitch).len());
        // Two whole disks and half of the third.
        let exact = 2.0 - 2.5 * std::f64::consts::PI * 0.09;
        assert!(
            (binder.area() - exact).abs() < 1e-3 * exact,
            "{}",
            binder.area()
        );
        assert!(binder.validate().is_ok());
        // Overlapping holes fall back on sampling.
        let two = bx.clone().minus(vec![grains[0].clone(), grains[0].clone()]);
        let one = bx.minus(vec![grains[0].clone()]);
        assert!((two.area() - one.area()).abs() < 1e-3 * one.area());
        let toml = r#"shape = "difference"
            base = { shape = "rectangle", lo = [0.0, 0.0], hi = [1.0, 1.0] }
            minus = [{ shape = "annulus", centre = [0.5, 0.5], inner = 0.1, outer = 0.2 }]"#;
        let g: Geometry = toml::from_str(toml).unwrap();
        assert!((g.area() - (1.0 - std::f64::consts::PI * 0.03)).abs() < 1e-12);
    }

    #[test]
    fn union_of_a_plate_and_disks() {
        let toml = r#"shape = "union"
            parts = [
                { shape = "rectangle", lo = [0.0, 0.0], hi = [0.1, 1.0] },
                { shape = "disk", centre = [0.25, 0.25], radius = 0.2 },
                { shape = "disk", centre = [0.25, 0.75], radius = 0.2 },
            ]"#;
        let u: Geometry = toml::from_str(toml).unwrap();
        assert!(u.validate().is_ok());
        let (lo, hi) = u.bounds();
        assert_eq!((lo, hi), (DVec2::new(0.0, 0.0), DVec2::new(0.45, 1.0)));
        // The disks overlap the plate (a segment 0.15 from their centres): sampled.
        let segment = 0.04 * (0.75f64).acos() - 0.15 * (0.04f64 - 0.0225).sqrt();
        let exact = 0.1 + 2.0 * (std::f64::consts::PI * 0.04 - segment);
        assert!(
            (u.area() - exact).abs() < 2e-3 * exact,
            "{} vs {exact}",
            u.area()
        );
        assert!(u.contains(DVec2::new(0.05, 0.5)) && u.contains(DVec2::new(0.4, 0.25)));
        let moved = u.translated(DVec2::new(0.0, 1.0));
        assert!(moved.contains(DVec2::new(0.4, 1.25)) && !moved.contains(DVec2::new(0.4, 0.25)));
        assert!((moved.area() - u.area()).abs() < 1e-12);
        let empty = Geometry::Union { parts: vec![] };
        assert!(empty.validate().unwrap_err().contains("parts = []"));
    }
}
