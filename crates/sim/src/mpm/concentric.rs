//! Bardenhagen et al.'s (1998) concentric cylinders as the checks see them: an inner
//! disk and a ring around it sharing its centre and its radius, each with its material
//! and temperature history; the static interface stress at any time, and when it first
//! reaches the bond.

use super::reference::{concentric_interface_stress, Layer};
use glam::DVec2;
use grains_mpm::{ContactLaw, Geometry, Setup};

/// The pair of bodies.
#[derive(Clone, Copy, Debug)]
pub struct Concentric {
    /// Index of the inner disk.
    pub inner: usize,
    /// Index of the ring.
    pub outer: usize,
    /// Common centre (m).
    pub centre: DVec2,
    /// Interface radius a (m).
    pub a: f64,
    /// Outer radius b (m).
    pub b: f64,
}

impl Concentric {
    /// The pair `inner`, `outer` if their shapes are a disk and a ring around it, with
    /// the same centre and the disk's radius as the ring's inner one; `Err` says why not.
    pub fn new(shapes: &[Geometry], inner: usize, outer: usize) -> Result<Self, String> {
        let Geometry::Disk { centre, radius } = shapes[inner] else {
            return Err("the inner body must be a disk".into());
        };
        let Geometry::Annulus {
            centre: c,
            inner: ri,
            outer: ro,
        } = shapes[outer]
        else {
            return Err("the outer body must be an annulus".into());
        };
        let (centre, c) = (DVec2::from(centre), DVec2::from(c));
        let tol = 1e-9 * ro;
        if (centre - c).length() > tol || (radius - ri).abs() > tol {
            return Err(format!(
                "the annulus (centre {c}, inner radius {ri}) must surround the disk (centre {centre}, radius {radius})"
            ));
        }
        Ok(Concentric {
            inner,
            outer,
            centre,
            a: radius,
            b: ro,
        })
    }

    fn layer(setup: &Setup, body: usize, t: f64) -> Layer {
        let b = &setup.bodies[body];
        let m = &setup.materials[b.material];
        let (bulk, shear) = m.moduli();
        let change = b.temperature.as_ref().map_or(0.0, |h| h.at(t) - h.at(0.0));
        Layer {
            bulk,
            shear,
            alpha_dt: m.expansion() * change,
        }
    }

    /// σ_rr(a) of the static bonded solution for the temperatures at time `t`.
    pub fn static_stress(&self, setup: &Setup, t: f64) -> f64 {
        concentric_interface_stress(
            self.a,
            self.b,
            Self::layer(setup, self.inner, t),
            Self::layer(setup, self.outer, t),
        )
    }

    /// The bond strength between the two (None: they are not bonded).
    pub fn bond(&self, setup: &Setup) -> Option<f64> {
        match setup.contact.get(self.inner, self.outer) {
            ContactLaw::Bonded { strength, .. } => Some(strength),
            _ => None,
        }
    }

    /// The first time before `t_end` at which the static interface tension reaches the
    /// bond (NaN if it never does).
    pub fn predicted_onset(&self, setup: &Setup, t_end: f64) -> f64 {
        let Some(bond) = self.bond(setup) else {
            return f64::NAN;
        };
        super::reference::first_time(|t| self.static_stress(setup, t), bond, 0.0, t_end, 20_000)
    }
}
