//! The region a packing fills: its boundaries, what "interior" means, and the
//! minimum-image rule of a periodic direction.

use glam::DVec2;

/// The container of a packing. Lengths in the units of the positions (SI for files).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Region {
    /// The ring `r_in ≤ |p − centre| ≤ r_out`; both circles are boundaries.
    Annulus {
        /// Centre of both circles.
        centre: DVec2,
        /// Inner radius.
        r_in: f64,
        /// Outer radius.
        r_out: f64,
    },
    /// The disk `|p − centre| ≤ radius`.
    Disk {
        /// Centre.
        centre: DVec2,
        /// Radius.
        radius: f64,
    },
    /// The box `lo ≤ p ≤ hi`; with `periodic_x` the left and right sides are
    /// not boundaries but wrap onto each other.
    Rectangle {
        /// Lower-left corner.
        lo: DVec2,
        /// Upper-right corner.
        hi: DVec2,
        /// Whether x is periodic with period `hi.x − lo.x`.
        periodic_x: bool,
    },
}

/// A circle as a closed poly-line of 256 points.
fn circle(centre: DVec2, r: f64) -> grains_core::plot::Outline {
    grains_core::plot::Outline {
        points: (0..256)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / 256.0;
                centre + r * DVec2::new(t.cos(), t.sin())
            })
            .collect(),
        closed: true,
    }
}

impl Region {
    /// The region's boundaries, to draw over a map of its particles (a periodic side
    /// is drawn too, as the cell's edge).
    pub fn outlines(&self) -> Vec<grains_core::plot::Outline> {
        match *self {
            Region::Annulus {
                centre,
                r_in,
                r_out,
            } => vec![circle(centre, r_in), circle(centre, r_out)],
            Region::Disk { centre, radius } => vec![circle(centre, radius)],
            Region::Rectangle { lo, hi, .. } => vec![grains_core::plot::Outline {
                points: vec![lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)],
                closed: true,
            }],
        }
    }

    /// Signed distance from `p` to the nearest boundary: positive inside, negative outside.
    /// Periodic sides are not boundaries.
    pub fn boundary_distance(&self, p: DVec2) -> f64 {
        match *self {
            Region::Annulus {
                centre,
                r_in,
                r_out,
            } => {
                let r = (p - centre).length();
                (r - r_in).min(r_out - r)
            }
            Region::Disk { centre, radius } => radius - (p - centre).length(),
            Region::Rectangle { lo, hi, periodic_x } => {
                let dy = (p.y - lo.y).min(hi.y - p.y);
                if periodic_x {
                    dy
                } else {
                    dy.min((p.x - lo.x).min(hi.x - p.x))
                }
            }
        }
    }

    /// Area of the region.
    pub fn area(&self) -> f64 {
        use std::f64::consts::PI;
        match *self {
            Region::Annulus { r_in, r_out, .. } => PI * (r_out * r_out - r_in * r_in),
            Region::Disk { radius, .. } => PI * radius * radius,
            Region::Rectangle { lo, hi, .. } => (hi.x - lo.x) * (hi.y - lo.y),
        }
    }

    /// The points at least `margin` from every boundary, as a region of the same kind,
    /// or `None` when nothing is left.
    pub fn shrink(&self, margin: f64) -> Option<Region> {
        match *self {
            Region::Annulus {
                centre,
                r_in,
                r_out,
            } => {
                let (a, b) = (r_in + margin, r_out - margin);
                (b > a).then_some(Region::Annulus {
                    centre,
                    r_in: a,
                    r_out: b,
                })
            }
            Region::Disk { centre, radius } => (radius > margin).then_some(Region::Disk {
                centre,
                radius: radius - margin,
            }),
            Region::Rectangle { lo, hi, periodic_x } => {
                let mx = if periodic_x { 0.0 } else { margin };
                let (lo2, hi2) = (lo + DVec2::new(mx, margin), hi - DVec2::new(mx, margin));
                (hi2.x > lo2.x && hi2.y > lo2.y).then_some(Region::Rectangle {
                    lo: lo2,
                    hi: hi2,
                    periodic_x,
                })
            }
        }
    }

    /// The period in x, if x is periodic.
    pub fn period_x(&self) -> Option<f64> {
        match *self {
            Region::Rectangle {
                lo,
                hi,
                periodic_x: true,
            } => Some(hi.x - lo.x),
            _ => None,
        }
    }

    /// `b − a` under the minimum-image rule of a periodic x direction.
    #[inline]
    pub fn delta(&self, a: DVec2, b: DVec2) -> DVec2 {
        let mut d = b - a;
        if let Some(l) = self.period_x() {
            d.x -= l * (d.x / l).round();
        }
        d
    }

    /// Axis-aligned bounding box `(lo, hi)`.
    pub fn bounds(&self) -> (DVec2, DVec2) {
        match *self {
            Region::Annulus { centre, r_out, .. } => {
                (centre - DVec2::splat(r_out), centre + DVec2::splat(r_out))
            }
            Region::Disk { centre, radius } => {
                (centre - DVec2::splat(radius), centre + DVec2::splat(radius))
            }
            Region::Rectangle { lo, hi, .. } => (lo, hi),
        }
    }

    /// The smallest walled rectangle holding every disk: the region assumed for data
    /// that does not say what it was packed in.
    pub fn bounding_box(pos: &[DVec2], radius: &[f64]) -> Region {
        let mut lo = DVec2::splat(f64::INFINITY);
        let mut hi = DVec2::splat(f64::NEG_INFINITY);
        for (p, r) in pos.iter().zip(radius) {
            lo = lo.min(*p - DVec2::splat(*r));
            hi = hi.max(*p + DVec2::splat(*r));
        }
        if pos.is_empty() {
            lo = DVec2::ZERO;
            hi = DVec2::ONE;
        }
        Region::Rectangle {
            lo,
            hi,
            periodic_x: false,
        }
    }

    /// One line describing the region, in the form the packing-file header uses and
    /// [`Region::parse`] reads back.
    pub fn describe(&self) -> String {
        match *self {
            Region::Annulus {
                centre,
                r_in,
                r_out,
            } => format!(
                "annulus centre_x={:e} centre_y={:e} r_in={:e} r_out={:e}",
                centre.x, centre.y, r_in, r_out
            ),
            Region::Disk { centre, radius } => {
                format!(
                    "disk centre_x={:e} centre_y={:e} radius={:e}",
                    centre.x, centre.y, radius
                )
            }
            Region::Rectangle { lo, hi, periodic_x } => format!(
                "rectangle lo_x={:e} lo_y={:e} hi_x={:e} hi_y={:e} periodic_x={}",
                lo.x, lo.y, hi.x, hi.y, periodic_x
            ),
        }
    }

    /// Reads what [`Region::describe`] writes; `None` if it is not such a line.
    pub fn parse(text: &str) -> Option<Region> {
        let mut words = text.split_whitespace();
        let kind = words.next()?;
        let mut kv = std::collections::BTreeMap::new();
        for w in words {
            let (k, v) = w.split_once('=')?;
            kv.insert(k, v);
        }
        let num =
            |k: &str| -> Option<f64> { kv.get(k)?.parse().ok().filter(|v: &f64| v.is_finite()) };
        let region = match kind {
            "annulus" => Region::Annulus {
                centre: DVec2::new(num("centre_x")?, num("centre_y")?),
                r_in: num("r_in")?,
                r_out: num("r_out")?,
            },
            "disk" => Region::Disk {
                centre: DVec2::new(num("centre_x")?, num("centre_y")?),
                radius: num("radius")?,
            },
            "rectangle" => Region::Rectangle {
                lo: DVec2::new(num("lo_x")?, num("lo_y")?),
                hi: DVec2::new(num("hi_x")?, num("hi_y")?),
                periodic_x: kv.get("periodic_x").map(|v| *v == "true").unwrap_or(false),
            },
            _ => return None,
        };
        region.is_valid().then_some(region)
    }

    /// Whether the region has positive area and sane radii.
    pub fn is_valid(&self) -> bool {
        match *self {
            Region::Annulus { r_in, r_out, .. } => r_in >= 0.0 && r_out > r_in,
            Region::Disk { radius, .. } => radius > 0.0,
            Region::Rectangle { lo, hi, .. } => hi.x > lo.x && hi.y > lo.y,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_and_shrink() {
        let a = Region::Annulus {
            centre: DVec2::ZERO,
            r_in: 1.0,
            r_out: 3.0,
        };
        assert!((a.boundary_distance(DVec2::new(2.0, 0.0)) - 1.0).abs() < 1e-12);
        assert!(a.boundary_distance(DVec2::new(0.5, 0.0)) < 0.0);
        let s = a.shrink(0.5).unwrap();
        assert!((s.area() - std::f64::consts::PI * (6.25 - 2.25)).abs() < 1e-12);
        assert!(a.shrink(1.0).is_none());
        let r = Region::Rectangle {
            lo: DVec2::ZERO,
            hi: DVec2::new(10.0, 2.0),
            periodic_x: true,
        };
        assert!((r.boundary_distance(DVec2::new(0.1, 1.0)) - 1.0).abs() < 1e-12);
        assert!((r.delta(DVec2::new(0.5, 0.0), DVec2::new(9.5, 0.0)).x + 1.0).abs() < 1e-12);
        assert_eq!(r.shrink(0.5).unwrap().bounds().0, DVec2::new(0.0, 0.5));
    }

    #[test]
    fn describe_round_trips() {
        for r in [
            Region::Annulus {
                centre: DVec2::new(1.0, -2.0),
                r_in: 0.01,
                r_out: 0.04,
            },
            Region::Disk {
                centre: DVec2::ZERO,
                radius: 1e-3,
            },
            Region::Rectangle {
                lo: DVec2::ZERO,
                hi: DVec2::new(1.0, 2.0),
                periodic_x: true,
            },
        ] {
            assert_eq!(Region::parse(&r.describe()), Some(r));
        }
        assert_eq!(
            Region::parse("annulus r_in=2 r_out=1 centre_x=0 centre_y=0"),
            None
        );
        assert_eq!(Region::parse("blob"), None);
    }
}
