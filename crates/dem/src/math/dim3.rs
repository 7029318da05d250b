//! Three dimensions: spheres.

use glam::{DMat3, DVec3};
use serde::{Deserialize, Serialize};

/// A position, velocity or force.
pub type Vector = DVec3;
/// An angular velocity or torque.
pub type AngVector = DVec3;
/// A contact's tangential spring, force or sliding velocity: a vector in the tangent
/// plane.
pub type Tangent = DVec3;
/// A stress or fabric tensor.
pub type Tensor = DMat3;
/// Number of axes.
pub const DIM: usize = 3;
/// Cells in the neighbour stencil around a cell (3 × 3 × 3).
pub const STENCIL: usize = 27;
/// I / (m r²) of a uniform sphere.
pub const INERTIA_FACTOR: f64 = 0.4;

/// Mass of a sphere.
#[inline]
pub fn mass(density: f64, r: f64) -> f64 {
    density * (4.0 / 3.0 * std::f64::consts::PI) * r * r * r
}

/// Volume of a sphere: what a particle's contact stress is averaged over.
#[inline]
pub fn measure(r: f64) -> f64 {
    4.0 / 3.0 * std::f64::consts::PI * r * r * r
}

/// Surface of a sphere: what a particle's contact pressure is spread over.
#[inline]
pub fn surface(r: f64) -> f64 {
    4.0 * std::f64::consts::PI * r * r
}

/// The ratio by which a cell's side grows to divide a cell count by `ratio`.
#[inline]
pub fn cell_growth(ratio: f64) -> f64 {
    ratio.cbrt()
}

/// Sliding velocity of the contact points in the tangent plane, for v = v_i − v_j and
/// spin = r_i ω_i + r_j ω_j: v − (v·n) n + spin × n.
#[inline(always)]
pub fn tangential_velocity(v: Vector, n: Vector, spin: AngVector) -> Tangent {
    v - v.dot(n) * n + spin.cross(n)
}

/// The tangential spring carried to the current normal: its normal part removed, as
/// LAMMPS `gran/hooke/history` does (a projection, without restoring the length).
#[inline(always)]
pub fn carry(xi: Tangent, n: Vector) -> Tangent {
    xi - xi.dot(n) * n
}

/// The tangential force as a vector (it already is one).
#[inline(always)]
pub fn tangent_vector(ft: Tangent, _n: Vector) -> Vector {
    ft
}

/// n × F_t (per unit radius): the torque of the tangential force on body i about its
/// centre is r_i (n × F_t), and on body j r_j (n × F_t) too.
#[inline(always)]
pub fn moment(ft: Tangent, n: Vector) -> AngVector {
    n.cross(ft)
}

/// The moment a × f.
#[inline(always)]
pub fn cross(a: Vector, f: Vector) -> AngVector {
    a.cross(f)
}

/// The velocity ω × a of a point at `a` from the axis of a body turning at ω.
#[inline(always)]
pub fn turn(w: AngVector, a: Vector) -> Vector {
    w.cross(a)
}

/// The tensor a ⊗ f.
#[inline]
pub fn outer(a: Vector, f: Vector) -> Tensor {
    DMat3::from_cols(a * f.x, a * f.y, a * f.z)
}

/// Geometry of a wall, as written in the scenario (`shape = "plane" | "disk" |
/// "rectangle" | "sphere" | "cylinder"`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "snake_case", deny_unknown_fields)]
pub enum WallShape {
    /// The infinite plane through `point` with normal `normal` (any length); spheres
    /// touch it from either side.
    Plane {
        /// A point of the plane (m).
        point: [f64; 3],
        /// Its normal (need not be unit).
        normal: [f64; 3],
    },
    /// The part of the plane through `centre` with normal `normal` between the circles
    /// of radius `hole` and `radius` about `centre` (a plate, or a silo's floor with its
    /// orifice; `radius` may be infinite and `hole` zero). Spheres touch either face and
    /// the two rims as edges.
    Disk {
        /// Centre (m).
        centre: [f64; 3],
        /// Its normal (need not be unit).
        normal: [f64; 3],
        /// Outer radius (m; infinite: no outer rim).
        radius: f64,
        /// Radius of the hole about the centre (m; zero: none).
        hole: f64,
    },
    /// The rectangle about `centre` in the plane with normal `normal`, `size[0]` long
    /// along `edge` (projected onto the plane) and `size[1]` across; spheres touch either
    /// face, the edges and the corners.
    Rectangle {
        /// Centre (m).
        centre: [f64; 3],
        /// Its normal (need not be unit).
        normal: [f64; 3],
        /// Direction of the first side (need not be unit nor in the plane).
        edge: [f64; 3],
        /// Side lengths along `edge` and across it (m).
        size: [f64; 2],
    },
    /// Sphere of `radius` about `centre`; `inside = true` keeps particles inside.
    Sphere {
        /// Centre (m).
        centre: [f64; 3],
        /// Radius (m).
        radius: f64,
        /// Particles live inside.
        inside: bool,
    },
    /// Infinite cylinder of `radius` about the axis through `point` along `axis`;
    /// `inside = true` keeps particles inside (a drum, a silo).
    Cylinder {
        /// A point on the axis (m).
        point: [f64; 3],
        /// Axis direction (need not be unit).
        axis: [f64; 3],
        /// Radius (m).
        radius: f64,
        /// Particles live inside.
        inside: bool,
    },
}

impl WallShape {
    /// Distance from `p` to the wall surface and the unit normal from `p` towards it.
    /// None when there is no defined normal (on the surface, at a centre or axis).
    #[inline]
    pub fn nearest(&self, p: Vector) -> Option<crate::walls::WallTouch> {
        match *self {
            WallShape::Plane { point, normal } => {
                let u = DVec3::from(normal).normalize_or_zero();
                crate::walls::face((p - DVec3::from(point)).dot(u), u)
            }
            WallShape::Disk {
                centre,
                normal,
                radius,
                hole,
            } => crate::walls::annulus(p, centre.into(), normal.into(), hole, radius),
            WallShape::Rectangle {
                centre,
                normal,
                edge,
                size,
            } => crate::walls::rectangle(p, centre.into(), normal.into(), edge.into(), size),
            WallShape::Sphere {
                centre,
                radius,
                inside,
            } => crate::walls::round(p, DVec3::from(centre), radius, inside),
            WallShape::Cylinder {
                point,
                axis,
                radius,
                inside,
            } => {
                let u = DVec3::from(axis).normalize_or_zero();
                let d = p - DVec3::from(point);
                // The point on the axis level with p: the cylinder is round about it.
                let foot = p - (d - d.dot(u) * u);
                crate::walls::round(p, foot, radius, inside)
            }
        }
    }

    /// The point wall torques are taken about.
    pub fn reference(&self) -> Vector {
        match *self {
            WallShape::Plane { point, .. } | WallShape::Cylinder { point, .. } => {
                DVec3::from(point)
            }
            WallShape::Disk { centre, .. }
            | WallShape::Rectangle { centre, .. }
            | WallShape::Sphere { centre, .. } => DVec3::from(centre),
        }
    }

    /// The direction the wall turns about when its spin keeps its shape (a plane's or a
    /// disk's normal, a cylinder's axis); None for a sphere (any axis) and a rectangle
    /// (none).
    pub fn axis(&self) -> Option<Vector> {
        match *self {
            WallShape::Plane { normal, .. } | WallShape::Disk { normal, .. } => {
                Some(DVec3::from(normal).normalize_or_zero())
            }
            WallShape::Cylinder { axis, .. } => Some(DVec3::from(axis).normalize_or_zero()),
            WallShape::Rectangle { .. } | WallShape::Sphere { .. } => None,
        }
    }

    /// Carries the wall by `d`.
    pub fn translate(&mut self, d: Vector) {
        let p = self.reference_mut();
        *p = (DVec3::from(*p) + d).to_array();
    }

    /// Puts the wall's reference point ([`Self::reference`]) at `at`.
    pub fn place(&mut self, at: Vector) {
        *self.reference_mut() = at.to_array();
    }

    fn reference_mut(&mut self) -> &mut [f64; 3] {
        match self {
            WallShape::Plane { point, .. } | WallShape::Cylinder { point, .. } => point,
            WallShape::Disk { centre, .. }
            | WallShape::Rectangle { centre, .. }
            | WallShape::Sphere { centre, .. } => centre,
        }
    }
}

/// Calls `$f::<P>($args)` with the domain's periodic axes as a const bit mask (bit a set:
/// axis a is periodic), so hot loops carry no per-axis branches on it.
#[macro_export]
macro_rules! with_image {
    ($domain:expr, $f:ident $(::<$($g:ty),*>)?, ($($arg:expr),*)) => {
        match $domain.periodic {
            [false, false, false] => $f::<$($($g,)*)? 0b000>($($arg),*),
            [true, false, false] => $f::<$($($g,)*)? 0b001>($($arg),*),
            [false, true, false] => $f::<$($($g,)*)? 0b010>($($arg),*),
            [true, true, false] => $f::<$($($g,)*)? 0b011>($($arg),*),
            [false, false, true] => $f::<$($($g,)*)? 0b100>($($arg),*),
            [true, false, true] => $f::<$($($g,)*)? 0b101>($($arg),*),
            [false, true, true] => $f::<$($($g,)*)? 0b110>($($arg),*),
            [true, true, true] => $f::<$($($g,)*)? 0b111>($($arg),*),
        }
    };
}

/// Components of an [`AngVector`].
pub const ANG: usize = 3;
/// Components of a [`Tangent`].
pub const TAN: usize = 3;

/// The tangential spring of a pair as seen from its other particle: the relative
/// displacement of one contact point against the other turns round.
#[inline(always)]
pub fn swapped(xi: Tangent) -> Tangent {
    -xi
}

/// A tangential or rolling spring carried to the current normal keeping its length, as
/// LAMMPS `pair granular` does: projected onto the tangent plane and rescaled, unless its
/// normal part is negligible (|ξ·n| k ≤ 10⁻¹⁰ `limit`, with `limit` the force cap).
#[inline(always)]
pub fn carry_keeping_length(xi: Tangent, n: Vector, stiffness: f64, limit: f64) -> Tangent {
    let along = xi.dot(n);
    if along.abs() * stiffness > 1e-10 * limit {
        let before = xi.length();
        let p = xi - along * n;
        let after = p.length();
        p * if after > 0.0 { before / after } else { 0.0 }
    } else {
        xi
    }
}

/// (ω_i − ω_j) × n_ji per unit effective radius: the rolling velocity of LAMMPS's `sds`
/// model (n_ji = −n, from j to i).
#[inline(always)]
pub fn roll_velocity(w_rel: AngVector, n: Vector) -> Tangent {
    n.cross(w_rel)
}

/// (ω_i − ω_j) · n_ji, the twisting rate.
#[inline(always)]
pub fn twist_rate(w_rel: AngVector, n: Vector) -> f64 {
    -w_rel.dot(n)
}

/// The couple M n_ji of a twisting moment M on body i.
#[inline(always)]
pub fn twist_couple(m: f64, n: Vector) -> AngVector {
    -m * n
}

/// A rolling spring as seen from the pair's other particle: the rolling displacement is
/// the same vector.
#[inline(always)]
pub fn roll_swapped(xi: Tangent) -> Tangent {
    xi
}
