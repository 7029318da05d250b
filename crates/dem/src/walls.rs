//! Rigid walls. A wall acts on a particle through the same contact law as a particle,
//! with infinite mass and no rotation. Their shapes depend on the dimension
//! ([`crate::math`]: segments and circles in 2D; planes, bounded plates, spheres and
//! cylinders in 3D). A wall may move ([`Motion`]): its surface velocity enters each
//! contact's relative velocity, so a turning drum drags the grains by friction.

pub use crate::math::WallShape;
use crate::math::{AngVector, Vector};
use crate::setup::Setup;
use crate::step::State;

/// How a wall moves: its surface at `x` moves at `velocity + omega × (x − reference)`
/// (about [`WallShape::reference`]). A translating wall is carried along by
/// [`Wall::advance`]; a turning one keeps its shape, as its spin is about its own axis
/// (the scenario refuses any other).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Motion {
    /// Velocity of translation (m/s).
    pub velocity: Vector,
    /// Angular velocity about the reference point (rad/s).
    pub omega: AngVector,
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
    /// Prescribed motion (default: at rest).
    pub motion: Motion,
}

impl Wall {
    /// A wall at rest.
    pub fn fixed(name: impl Into<String>, shape: WallShape, material: Option<u16>) -> Self {
        Wall {
            name: name.into(),
            shape,
            material,
            motion: Motion::default(),
        }
    }

    /// Velocity of the wall's surface at `x`.
    #[inline]
    pub fn surface_velocity(&self, x: Vector) -> Vector {
        self.motion.velocity + crate::math::turn(self.motion.omega, x - self.shape.reference())
    }

    /// Whether the wall changes place, so that no particle may be left off its watch
    /// between list rebuilds (the Verlet skin only bounds the particles' motion).
    #[inline]
    pub fn translates(&self) -> bool {
        self.motion.velocity != Vector::ZERO
    }

    /// Carries a translating wall through a step `dt`.
    pub fn advance(&mut self, dt: f64) {
        if self.translates() {
            self.shape.translate(self.motion.velocity * dt);
        }
    }
}

/// Where a wall has got to: engine state ([`State::walls`]), advanced by
/// [`advance_walls`] and kept in checkpoints, so that a resumed run places its walls
/// where the straight run left them instead of replaying their steps.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pose {
    /// The wall's reference point ([`WallShape::reference`]) now; its offset is this
    /// less the reference point the scenario gave.
    pub at: Vector,
    /// Angle turned through about the reference point (rad; in 3D a vector along the
    /// spin axis, ∫ ω dt, which is exact as a wall turns about a fixed axis).
    pub angle: AngVector,
}

/// Each wall's pose where the set-up has it, turned through no angle.
pub fn poses(setup: &Setup) -> Vec<Pose> {
    setup
        .walls
        .iter()
        .map(|w| Pose {
            at: w.shape.reference(),
            angle: AngVector::default(),
        })
        .collect()
}

/// Carries every moving wall through a step `dt`: its pose advanced, its shape placed
/// there. Called before the step, whose forces are those at its end, t + dt. The pose
/// is advanced as the shape itself used to be (`at + v dt`), so runs keep their bits.
pub fn advance_walls(setup: &mut Setup, state: &mut State, dt: f64) {
    if state.walls.len() != setup.walls.len() {
        state.walls = poses(setup);
    }
    for (w, pose) in setup.walls.iter_mut().zip(&mut state.walls) {
        if w.translates() {
            pose.at += w.motion.velocity * dt;
            w.shape.place(pose.at);
        }
        if w.motion.omega != AngVector::default() {
            pose.angle += w.motion.omega * dt;
        }
    }
}

/// Places every wall's shape at its pose in `state` (a run resumed from a checkpoint).
pub fn place_walls(setup: &mut Setup, state: &State) {
    for (w, pose) in setup.walls.iter_mut().zip(&state.walls) {
        w.shape.place(pose.at);
    }
}

/// A particle–wall contact: unit normal from the particle's centre towards the wall.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallTouch {
    /// Unit normal pointing from the disk centre to the contact point.
    pub normal: Vector,
    /// Distance from the particle's centre to the wall surface along the normal (m).
    pub distance: f64,
}

/// A wall that particle `i` overlaps now, as the diagnostics see it: the wall's index,
/// the slot of the particle's stored wall spring and history, the touch, the overlap
/// and the materials of the particle and of the wall (the particle's when the wall
/// names none).
#[derive(Clone, Copy, Debug)]
pub struct WallOverlap {
    /// The wall's index in the set-up.
    pub wall: usize,
    /// Where the pair's spring and history are stored (`i * walls + wall`).
    pub slot: usize,
    /// Normal and distance from the particle's centre.
    pub touch: WallTouch,
    /// Depth of the overlap (m, positive).
    pub overlap: f64,
    /// The particle's material and the wall's.
    pub materials: (usize, usize),
}

/// The walls particle `i` of `p` overlaps, in wall order: what the ledger's stored
/// springs and the contact stress both walk, so they count the same contacts.
pub fn overlapping_walls<'a>(
    setup: &'a Setup,
    p: &'a crate::particles::Particles,
    i: usize,
) -> impl Iterator<Item = WallOverlap> + 'a {
    let nw = setup.walls.len();
    setup.walls.iter().enumerate().filter_map(move |(w, wall)| {
        let touch = wall.shape.nearest(p.pos[i])?;
        let overlap = p.radius[i] - touch.distance;
        if overlap <= 0.0 {
            return None;
        }
        let mi = p.material[i] as usize;
        Some(WallOverlap {
            wall: w,
            slot: i * nw + w,
            touch,
            overlap,
            materials: (mi, wall.material.map_or(mi, |m| m as usize)),
        })
    })
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

/// The touch of `p` on the flat ring about `c` (unit normal `u`) between the radii
/// `inner` and `outer`: its face where `p` projects onto the ring, else the nearest
/// point of the rim it projects past (an edge: the normal points at that point).
#[cfg(feature = "dim3")]
#[inline]
pub fn annulus(p: Vector, c: Vector, u: Vector, inner: f64, outer: f64) -> Option<WallTouch> {
    let u = u.normalize_or_zero();
    let d = p - c;
    let h = d.dot(u);
    let q = d - h * u;
    let rho = q.length();
    let rim = if rho < inner {
        inner
    } else if rho > outer {
        outer
    } else {
        return face(h, u);
    };
    if rho == 0.0 {
        return None;
    }
    edge(p, c + q * (rim / rho))
}

/// The touch of `p` on the rectangle about `c` (normal `u`, sides `size` along `e`
/// and across): its face, an edge or a corner, whichever is nearest.
#[cfg(feature = "dim3")]
#[inline]
pub fn rectangle(p: Vector, c: Vector, u: Vector, e: Vector, size: [f64; 2]) -> Option<WallTouch> {
    let u = u.normalize_or_zero();
    let e1 = (e - e.dot(u) * u).normalize_or_zero();
    let e2 = u.cross(e1);
    let d = p - c;
    let (a, b) = (d.dot(e1), d.dot(e2));
    let (ca, cb) = (
        a.clamp(-0.5 * size[0], 0.5 * size[0]),
        b.clamp(-0.5 * size[1], 0.5 * size[1]),
    );
    if (ca, cb) == (a, b) {
        return face(d.dot(u), u);
    }
    edge(p, c + ca * e1 + cb * e2)
}

/// The touch on a flat face of unit normal `u` of a point at height `h` above it (along
/// `u`; either side).
#[cfg(feature = "dim3")]
#[inline]
pub fn face(h: f64, u: Vector) -> Option<WallTouch> {
    (h != 0.0).then(|| WallTouch {
        normal: -u * h.signum(),
        distance: h.abs(),
    })
}

/// The touch of `p` on the point `x` of an edge.
#[cfg(feature = "dim3")]
#[inline]
fn edge(p: Vector, x: Vector) -> Option<WallTouch> {
    let v = x - p;
    let dist = v.length();
    (dist > 0.0).then(|| WallTouch {
        normal: v / dist,
        distance: dist,
    })
}

#[cfg(all(test, feature = "dim3"))]
mod tests3 {
    use super::*;
    use glam::DVec3;

    #[test]
    fn annulus_face_hole_rim_and_outer_rim() {
        let floor = WallShape::Disk {
            centre: [0.0, 0.0, 0.0],
            normal: [0.0, 0.0, 2.0],
            radius: 1.0,
            hole: 0.25,
        };
        let t = floor.nearest(DVec3::new(0.5, 0.0, 0.1)).unwrap();
        assert_eq!((t.distance, t.normal), (0.1, -DVec3::Z));
        // Above the orifice: the rim circle is the contact (3-4-5 triangle).
        let t = floor.nearest(DVec3::new(0.0, 0.05, 0.15)).unwrap();
        assert!((t.distance - 0.25).abs() < 1e-15);
        assert!((t.normal - DVec3::new(0.0, 0.8, -0.6)).length() < 1e-15);
        let t = floor.nearest(DVec3::new(1.3, 0.0, -0.4)).unwrap();
        assert!((t.distance - 0.5).abs() < 1e-15);
        assert!((t.normal - DVec3::new(-0.6, 0.0, 0.8)).length() < 1e-15);
        assert!(floor.nearest(DVec3::new(0.0, 0.0, 0.3)).is_none());
    }

    #[test]
    fn rectangle_face_edge_and_corner() {
        let plate = WallShape::Rectangle {
            centre: [0.0, 0.0, 0.0],
            normal: [0.0, 0.0, 1.0],
            edge: [1.0, 0.0, 0.5],
            size: [2.0, 1.0],
        };
        let t = plate.nearest(DVec3::new(0.9, 0.4, -0.2)).unwrap();
        assert_eq!((t.distance, t.normal), (0.2, DVec3::Z));
        let t = plate.nearest(DVec3::new(1.3, 0.0, 0.4)).unwrap();
        assert!((t.distance - 0.5).abs() < 1e-15);
        let t = plate.nearest(DVec3::new(2.0, 1.5, 0.0)).unwrap();
        assert!((t.distance - 2f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn a_turning_cylinder_drags_its_surface_and_a_moving_plane_moves() {
        let mut w = Wall::fixed(
            "drum",
            WallShape::Cylinder {
                point: [0.0, 0.0, 0.0],
                axis: [0.0, 1.0, 0.0],
                radius: 1.0,
                inside: true,
            },
            None,
        );
        w.motion.omega = DVec3::new(0.0, 2.0, 0.0);
        // ω × (x − axis point): at the bottom (0, 3, −1) the surface moves along −x.
        assert_eq!(
            w.surface_velocity(DVec3::new(0.0, 3.0, -1.0)),
            DVec3::new(-2.0, 0.0, 0.0)
        );
        w.motion.velocity = DVec3::new(0.0, 0.0, 0.5);
        w.advance(0.2);
        assert_eq!(w.shape.reference(), DVec3::new(0.0, 0.0, 0.1));
        w.shape.place(DVec3::new(1.0, 0.0, 0.0));
        assert_eq!(w.shape.reference(), DVec3::X);
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
