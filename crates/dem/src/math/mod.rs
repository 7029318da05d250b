//! The dimension of the engine lives here, and only here.
//!
//! The same source compiles as the 2D engine (`grains-dem`, feature `dim2`: disks, a
//! scalar spin, the tangential spring as a scalar along t = (−n_y, n_x)) and as the 3D
//! engine (`grains-dem3d`, feature `dim3`: spheres, vector spins, the tangential spring
//! as a vector kept in the tangent plane), as rapier2d and rapier3d are made from one
//! tree. Every other module is written in terms of the names below: [`Vector`], the
//! angular vector [`AngVector`] (a scalar in 2D), the tangential quantity [`Tangent`]
//! (a component along t in 2D, a vector in 3D), the stress [`Tensor`], the cell stencil
//! and the few kinematic rules that differ between the two (the relative sliding
//! velocity, the moment of a tangential force, how the spring follows a turning normal).
//!
//! In 2D each rule is written with the exact floating-point operations the engine used
//! before the seam, so 2D results are bitwise what they were.

#[cfg(all(feature = "dim2", feature = "dim3"))]
compile_error!(
    "grains-dem is built for one dimension: features `dim2` and `dim3` exclude each other"
);
#[cfg(not(any(feature = "dim2", feature = "dim3")))]
compile_error!("grains-dem needs feature `dim2` or `dim3`");

#[cfg(feature = "dim2")]
mod dim2;
#[cfg(feature = "dim2")]
pub use dim2::*;

#[cfg(feature = "dim3")]
mod dim3;
#[cfg(feature = "dim3")]
pub use dim3::*;

use std::ops::{Add, Mul, Neg, Sub};

/// A value made of a fixed number of `f64` components (a scalar, a 2- or 3-vector): how
/// kernels lay it out in per-component arrays, how checkpoints and fingerprints walk it.
pub trait Components:
    Copy
    + Default
    + PartialEq
    + Send
    + Sync
    + std::fmt::Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Neg<Output = Self>
    + Mul<f64, Output = Self>
{
    /// Number of components.
    const N: usize;
    /// The zero value.
    const ZERO: Self;
    /// Component `a` (< `N`).
    fn get(self, a: usize) -> f64;
    /// The value with the given components (`c.len() >= N`).
    fn from_slice(c: &[f64]) -> Self;
    /// Reads slot `t` of per-component arrays (`lanes.len() >= N`).
    #[inline(always)]
    fn read<const B: usize>(lanes: &[[f64; B]], t: usize) -> Self {
        let mut c = [0.0; 3];
        for a in 0..Self::N {
            c[a] = lanes[a][t];
        }
        Self::from_slice(&c)
    }
    /// Writes the value into slot `t` of per-component arrays.
    #[inline(always)]
    fn write<const B: usize>(self, lanes: &mut [[f64; B]], t: usize) {
        for a in 0..Self::N {
            lanes[a][t] = self.get(a);
        }
    }
    /// Every component finite.
    fn finite(self) -> bool {
        (0..Self::N).all(|a| self.get(a).is_finite())
    }
    /// The components in order, flattened over a slice of values.
    fn flatten(v: &[Self]) -> Vec<f64> {
        v.iter()
            .flat_map(|x| (0..Self::N).map(move |a| x.get(a)))
            .collect()
    }
    /// The values of a flattened slice (`f.len()` a multiple of `N`).
    fn unflatten(f: &[f64]) -> Vec<Self> {
        f.chunks_exact(Self::N).map(Self::from_slice).collect()
    }
}

impl Components for f64 {
    const N: usize = 1;
    const ZERO: Self = 0.0;
    #[inline(always)]
    fn get(self, _: usize) -> f64 {
        self
    }
    #[inline(always)]
    fn from_slice(c: &[f64]) -> Self {
        c[0]
    }
    #[inline(always)]
    fn read<const B: usize>(lanes: &[[f64; B]], t: usize) -> Self {
        lanes[0][t]
    }
    #[inline(always)]
    fn write<const B: usize>(self, lanes: &mut [[f64; B]], t: usize) {
        lanes[0][t] = self;
    }
}

impl Components for glam::DVec2 {
    const N: usize = 2;
    const ZERO: Self = glam::DVec2::ZERO;
    #[inline(always)]
    fn get(self, a: usize) -> f64 {
        self[a]
    }
    #[inline(always)]
    fn from_slice(c: &[f64]) -> Self {
        glam::DVec2::new(c[0], c[1])
    }
    #[inline(always)]
    fn read<const B: usize>(lanes: &[[f64; B]], t: usize) -> Self {
        glam::DVec2::new(lanes[0][t], lanes[1][t])
    }
    #[inline(always)]
    fn write<const B: usize>(self, lanes: &mut [[f64; B]], t: usize) {
        lanes[0][t] = self.x;
        lanes[1][t] = self.y;
    }
}

impl Components for glam::DVec3 {
    const N: usize = 3;
    const ZERO: Self = glam::DVec3::ZERO;
    #[inline(always)]
    fn get(self, a: usize) -> f64 {
        self[a]
    }
    #[inline(always)]
    fn from_slice(c: &[f64]) -> Self {
        glam::DVec3::new(c[0], c[1], c[2])
    }
    #[inline(always)]
    fn read<const B: usize>(lanes: &[[f64; B]], t: usize) -> Self {
        glam::DVec3::new(lanes[0][t], lanes[1][t], lanes[2][t])
    }
    #[inline(always)]
    fn write<const B: usize>(self, lanes: &mut [[f64; B]], t: usize) {
        lanes[0][t] = self.x;
        lanes[1][t] = self.y;
        lanes[2][t] = self.z;
    }
}

/// The tangential quantities of a contact (spring, force, sliding velocity): a component
/// along t in 2D, a vector in the tangent plane in 3D.
pub trait TangentOps: Components {
    /// Inner product.
    fn dot(self, o: Self) -> f64;
    /// Magnitude.
    fn norm(self) -> f64;
    /// The value scaled to magnitude `m` (the value is not zero).
    fn with_norm(self, m: f64) -> Self;
    /// c·x·x, evaluated left to right in 2D (c x x), as c |x|² in 3D.
    fn quad(self, c: f64) -> f64;
}

impl TangentOps for f64 {
    #[inline(always)]
    fn dot(self, o: Self) -> f64 {
        self * o
    }
    #[inline(always)]
    fn norm(self) -> f64 {
        self.abs()
    }
    #[inline(always)]
    fn with_norm(self, m: f64) -> Self {
        m.copysign(self)
    }
    #[inline(always)]
    fn quad(self, c: f64) -> f64 {
        c * self * self
    }
}

impl TangentOps for glam::DVec3 {
    #[inline(always)]
    fn dot(self, o: Self) -> f64 {
        glam::DVec3::dot(self, o)
    }
    #[inline(always)]
    fn norm(self) -> f64 {
        self.length()
    }
    #[inline(always)]
    fn with_norm(self, m: f64) -> Self {
        self * (m / self.length())
    }
    #[inline(always)]
    fn quad(self, c: f64) -> f64 {
        c * self.length_squared()
    }
}

/// Writes an array of vectors, angular vectors or tangential values to a checkpoint.
pub fn put<T: Stored>(w: &mut impl std::io::Write, v: &[T]) -> std::io::Result<()> {
    T::put_slice(w, v)
}

/// Reads what [`put`] wrote: at most `limit` values.
pub fn get<T: Stored>(
    r: &mut impl std::io::Read,
    limit: usize,
) -> Result<Vec<T>, grains_core::snapshot::SnapshotError> {
    T::get_vec(r, limit)
}

/// How an array of [`Components`] is laid out in a checkpoint: 2D vectors as
/// `grains_core::snapshot`'s vector arrays (the layout 2D checkpoints always had), other
/// values as their components in a flat `f64` array.
pub trait Stored: Components {
    /// Writes the array.
    fn put_slice(w: &mut impl std::io::Write, v: &[Self]) -> std::io::Result<()> {
        grains_core::snapshot::put_f64(w, &Self::flatten(v))
    }
    /// Reads an array of at most `limit` values.
    fn get_vec(
        r: &mut impl std::io::Read,
        limit: usize,
    ) -> Result<Vec<Self>, grains_core::snapshot::SnapshotError> {
        let f = grains_core::snapshot::get_f64(r, limit.saturating_mul(Self::N))?;
        if f.len() % Self::N != 0 {
            return Err(grains_core::snapshot::SnapshotError::Invalid(format!(
                "{} numbers do not make values of {} components",
                f.len(),
                Self::N
            )));
        }
        Ok(Self::unflatten(&f))
    }
}

impl Stored for f64 {}
impl Stored for glam::DVec3 {}

impl Stored for glam::DVec2 {
    fn put_slice(w: &mut impl std::io::Write, v: &[Self]) -> std::io::Result<()> {
        grains_core::snapshot::put_vec2(w, v)
    }
    fn get_vec(
        r: &mut impl std::io::Read,
        limit: usize,
    ) -> Result<Vec<Self>, grains_core::snapshot::SnapshotError> {
        grains_core::snapshot::get_vec2(r, limit)
    }
}
