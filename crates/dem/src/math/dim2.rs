//! Two dimensions: disks per unit thickness.

use glam::{DMat2, DVec2};
use serde::{Deserialize, Serialize};

/// A position, velocity or force.
pub type Vector = DVec2;
/// An angular velocity or torque: about z, a scalar in 2D.
pub type AngVector = f64;
/// A contact's tangential spring, force or sliding velocity: its component along
/// t = (−n_y, n_x).
pub type Tangent = f64;
/// A stress or fabric tensor.
pub type Tensor = DMat2;
/// Number of axes.
pub const DIM: usize = 2;
/// Cells in the neighbour stencil around a cell (3 × 3).
pub const STENCIL: usize = 9;
/// I / (m r²) of a uniform disk.
pub const INERTIA_FACTOR: f64 = 0.5;

/// Mass per unit thickness of a disk.
#[inline]
pub fn mass(density: f64, r: f64) -> f64 {
    density * std::f64::consts::PI * r * r
}

/// Area of a disk: what a particle's contact stress is averaged over.
#[inline]
pub fn measure(r: f64) -> f64 {
    std::f64::consts::PI * r * r
}

/// Perimeter of a disk: what a particle's contact pressure is spread over.
#[inline]
pub fn surface(r: f64) -> f64 {
    std::f64::consts::TAU * r
}

/// The ratio by which a cell's side grows to divide a cell count by `ratio`.
#[inline]
pub fn cell_growth(ratio: f64) -> f64 {
    ratio.sqrt()
}

/// Sliding velocity of the contact points along t, for v = v_i − v_j and spin =
/// r_i ω_i + r_j ω_j (the rotational part ω × n of the contact points' velocity).
#[inline(always)]
pub fn tangential_velocity(v: Vector, n: Vector, spin: AngVector) -> Tangent {
    (v.y * n.x - v.x * n.y) + spin
}

/// The tangential spring carried to the current normal: in 2D it is a component along
/// t, which turns with n.
#[inline(always)]
pub fn carry(xi: Tangent, _n: Vector) -> Tangent {
    xi
}

/// The tangential force as a vector: F_t t.
#[inline(always)]
pub fn tangent_vector(ft: Tangent, n: Vector) -> Vector {
    ft * n.perp()
}

/// n × F_t (per unit radius): the torque of the tangential force on body i about its
/// centre is r_i (n × F_t), and on body j r_j (n × F_t) too.
#[inline(always)]
pub fn moment(ft: Tangent, _n: Vector) -> AngVector {
    ft
}

/// The moment a × f.
#[inline(always)]
pub fn cross(a: Vector, f: Vector) -> AngVector {
    a.perp_dot(f)
}

/// The velocity ω × a of a point at `a` from the centre of a body turning at ω.
#[inline(always)]
pub fn turn(w: AngVector, a: Vector) -> Vector {
    w * a.perp()
}

/// The tensor a ⊗ f.
#[inline]
pub fn outer(a: Vector, f: Vector) -> Tensor {
    DMat2::from_cols(a * f.x, a * f.y)
}

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

impl WallShape {
    /// Distance from `p` to the wall surface and the unit normal from `p` towards it.
    /// None when the point sits exactly on the surface (no defined normal).
    #[inline]
    pub fn nearest(&self, p: Vector) -> Option<crate::walls::WallTouch> {
        use crate::walls::WallTouch;
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
            } => crate::walls::round(p, DVec2::from(centre), radius, inside),
        }
    }

    /// The point wall torques are taken about: a segment's midpoint, a circle's centre.
    pub fn reference(&self) -> Vector {
        match *self {
            WallShape::Segment { a, b } => 0.5 * (DVec2::from(a) + DVec2::from(b)),
            WallShape::Circle { centre, .. } => DVec2::from(centre),
        }
    }

    /// Carries the wall by `d`.
    pub fn translate(&mut self, d: Vector) {
        let shift = |p: &mut [f64; 2]| *p = (DVec2::from(*p) + d).to_array();
        match self {
            WallShape::Segment { a, b } => {
                shift(a);
                shift(b);
            }
            WallShape::Circle { centre, .. } => shift(centre),
        }
    }

    /// Puts the wall's reference point ([`Self::reference`]) at `at` (a segment is
    /// carried by the difference, which rounds: no 2D front end moves walls yet).
    pub fn place(&mut self, at: Vector) {
        match self {
            WallShape::Segment { .. } => self.translate(at - self.reference()),
            WallShape::Circle { centre, .. } => *centre = at.to_array(),
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

/// Calls `$f::<P>($args)` with the domain's periodic axes as a const bit mask (bit a set:
/// axis a is periodic), so hot loops carry no per-axis branches on it.
#[macro_export]
macro_rules! with_image {
    ($domain:expr, $f:ident $(::<$($g:ty),*>)?, ($($arg:expr),*)) => {
        match $domain.periodic {
            [false, false] => $f::<$($($g,)*)? 0b00>($($arg),*),
            [true, false] => $f::<$($($g,)*)? 0b01>($($arg),*),
            [false, true] => $f::<$($($g,)*)? 0b10>($($arg),*),
            [true, true] => $f::<$($($g,)*)? 0b11>($($arg),*),
        }
    };
}

/// Components of an [`AngVector`] (1 in 2D).
pub const ANG: usize = 1;
/// Components of a [`Tangent`] (1 in 2D).
pub const TAN: usize = 1;

/// The tangential spring of a pair as seen from its other particle: the relative
/// displacement and t = (−n_y, n_x) both turn round, so its component along t is the same.
#[inline(always)]
pub fn swapped(xi: Tangent) -> Tangent {
    xi
}

/// A tangential or rolling spring carried to the current normal keeping its length (LAMMPS
/// `pair granular`): in 2D its component along t already follows the normal.
#[inline(always)]
pub fn carry_keeping_length(xi: Tangent, _n: Vector, _stiffness: f64, _limit: f64) -> Tangent {
    xi
}

/// (ω_i − ω_j) × n_ji per unit effective radius: the rolling velocity of LAMMPS's `sds`
/// model (n_ji = −n from j to i), as its component along t.
#[inline(always)]
pub fn roll_velocity(w_rel: AngVector, _n: Vector) -> Tangent {
    -w_rel
}

/// (ω_i − ω_j) · n_ji, the twisting rate: none in 2D.
#[inline(always)]
pub fn twist_rate(_w_rel: AngVector, _n: Vector) -> f64 {
    0.0
}

/// The couple M n_ji of a twisting moment M on body i: none in 2D.
#[inline(always)]
pub fn twist_couple(_m: f64, _n: Vector) -> AngVector {
    0.0
}

/// A rolling spring as seen from the pair's other particle: the rolling displacement is
/// the same vector, and t turns round.
#[inline(always)]
pub fn roll_swapped(xi: Tangent) -> Tangent {
    -xi
}
