//! Rigid walls: straight segments and circles. A wall acts on a disk through the same
//! contact law as a particle, with infinite mass and no rotation.

use glam::DVec2;
use serde::{Deserialize, Serialize};

/// Geometry of a wall, as written in the scenario (`shape = "segment" | "circle"`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "snake_case", deny_unknown_fields)]
pub enum WallShape {
    /// Segment from `a` to `b`; disks touch it from either side and at its end points.
    Segment {
        /// First end point (m).
        a: [f64; 2],
        /// Second end point (m).
        b: [f64; 2],
    },
    /// Circle of `radius` about `centre`; `inside = true` keeps disks inside (a drum or
    /// container), `false` keeps them outside (an obstacle).
    Circle {
        /// Centre (m).
        centre: [f64; 2],
        /// Radius (m).
        radius: f64,
        /// Disks live inside the circle.
        inside: bool,
    },
}

/// A wall with its contact material (None: the touching particle's own material).
#[derive(Clone, Debug, PartialEq)]
pub struct Wall {
    /// Name used in history columns.
    pub name: String,
    /// Geometry.
    pub shape: WallShape,
    /// Material index, or None to use the particle's material.
    pub material: Option<u16>,
}

/// A disk–wall contact: unit normal from the disk centre towards the wall and overlap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallTouch {
    /// Unit normal pointing from the disk centre to the contact point.
    pub normal: DVec2,
    /// Distance from the disk centre to the wall surface along the normal (m).
    pub distance: f64,
}

impl WallShape {
    /// Distance from `p` to the wall surface and the unit normal from `p` towards it.
    /// None when the point sits exactly on the surface (no defined normal).
    #[inline]
    pub fn nearest(&self, p: DVec2) -> Option<WallTouch> {
        match *self {
            WallShape::Segment { a, b } => {
                let a = DVec2::from(a);
                let ab = DVec2::from(b) - a;
                let len2 = ab.length_squared();
                let t = if len2 > 0.0 {
                    ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let d = a + ab * t - p;
                let dist = d.length();
                (dist > 0.0).then(|| WallTouch {
                    normal: d / dist,
                    distance: dist,
                })
            }
            WallShape::Circle {
                centre,
                radius,
                inside,
            } => {
                let c = DVec2::from(centre);
                let d = p - c;
                let rho = d.length();
                if rho == 0.0 {
                    return None;
                }
                let radial = d / rho;
                if inside {
                    Some(WallTouch {
                        normal: radial,
                        distance: radius - rho,
                    })
                } else {
                    Some(WallTouch {
                        normal: -radial,
                        distance: rho - radius,
                    })
                }
            }
        }
    }

    /// Points along the wall for drawing (a segment: its ends; a circle: a polygon).
    pub fn outline(&self) -> Vec<DVec2> {
        match *self {
            WallShape::Segment { a, b } => vec![DVec2::from(a), DVec2::from(b)],
            WallShape::Circle { centre, radius, .. } => {
                let n = 256;
                (0..=n)
                    .map(|k| {
                        let t = std::f64::consts::TAU * k as f64 / n as f64;
                        DVec2::from(centre) + radius * DVec2::new(t.cos(), t.sin())
                    })
                    .collect()
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_distance_and_normal() {
        let w = WallShape::Segment {
            a: [0.0, 0.0],
            b: [2.0, 0.0],
        };
        let t = w.nearest(DVec2::new(1.0, 0.5)).unwrap();
        assert_eq!(t.distance, 0.5);
        assert_eq!(t.normal, DVec2::new(0.0, -1.0));
        let t = w.nearest(DVec2::new(3.0, 0.0)).unwrap();
        assert_eq!(t.distance, 1.0);
        assert_eq!(t.normal, DVec2::new(-1.0, 0.0));
    }

    #[test]
    fn circle_inside_and_outside() {
        let inside = WallShape::Circle {
            centre: [0.0, 0.0],
            radius: 2.0,
            inside: true,
        };
        let t = inside.nearest(DVec2::new(1.5, 0.0)).unwrap();
        assert_eq!(t.distance, 0.5);
        assert_eq!(t.normal, DVec2::X);
        let outside = WallShape::Circle {
            centre: [0.0, 0.0],
            radius: 1.0,
            inside: false,
        };
        let t = outside.nearest(DVec2::new(0.0, 1.5)).unwrap();
        assert_eq!(t.distance, 0.5);
        assert_eq!(t.normal, -DVec2::Y);
    }
}
