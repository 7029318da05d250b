//! Rigid walls. A wall acts on a particle through the same contact law as a particle,
//! with infinite mass and no rotation. Their shapes depend on the dimension
//! ([`crate::math`]: segments and circles in 2D; planes, spheres and cylinders in 3D).

use crate::math::Vector;
pub use crate::math::WallShape;

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

/// A particle–wall contact: unit normal from the particle's centre towards the wall.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallTouch {
    /// Unit normal pointing from the disk centre to the contact point.
    pub normal: Vector,
    /// Distance from the particle's centre to the wall surface along the normal (m).
    pub distance: f64,
}

/// A round wall (a circle, a sphere, a cylinder about the point level with `p`) of
/// `radius` about `c`: particles inside or outside.
#[inline]
pub fn round(p: Vector, c: Vector, radius: f64, inside: bool) -> Option<WallTouch> {
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

#[cfg(all(test, feature = "dim2"))]
mod tests {
    use super::*;
    use glam::DVec2;

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
