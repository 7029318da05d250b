//! Outside forces on the particles of DEM and FEM–DEM runs: fields a script adds (a
//! drag, a load, LAMMPS's `fix external`), applied in the DEM step's `post_force` hook
//! after every contact force is summed and before the closing kick, so they enter the
//! velocity-Verlet update exactly as contact forces do. The same fields serve 2D runs
//! (over [`grains_dem::Particles`], the default) and 3D ones (over
//! [`grains_dem3d::Particles`]).

use grains_dem::Particles;

/// What an outside force may fail with (a script's exception, a wrong shape).
pub type ForceError = Box<dyn std::error::Error + Send + Sync>;

/// A force field over the particles `P` (disks by default, or spheres).
pub trait OutsideForce<P = Particles>: Send {
    /// Adds its forces to `p.force` (and torques to `p.torque`), the particles in the
    /// engine's storage order (`p.id` names them), positions at `time` (the end of the
    /// step being taken) and velocities at the half step.
    fn add(&mut self, time: f64, p: &mut P) -> Result<(), ForceError>;
}

/// The outside forces of a run, and the first error one of them raised (the step it was
/// raised in went on without the failing field; the caller takes the error after it).
pub struct Outside<P = Particles> {
    /// The fields, applied in order.
    pub fields: Vec<Box<dyn OutsideForce<P>>>,
    /// The first error, until taken.
    pub error: Option<ForceError>,
}

impl<P> Default for Outside<P> {
    fn default() -> Self {
        Outside {
            fields: Vec::new(),
            error: None,
        }
    }
}

impl<P> Outside<P> {
    /// Adds every field's forces at `time`.
    pub fn apply(&mut self, time: f64, p: &mut P) {
        if self.error.is_some() {
            return;
        }
        for f in &mut self.fields {
            if let Err(e) = f.add(time, p) {
                self.error = Some(e);
                return;
            }
        }
    }

    /// Whether there are no fields.
    pub fn is_empty(&self) -> bool {
        self.fields.is_empty()
    }
}

/// The DEM step's hook that applies them.
pub struct Hook<'a, P = Particles> {
    /// The fields.
    pub outside: &'a mut Outside<P>,
    /// The time at the end of the step.
    pub time: f64,
}

impl grains_dem::Hooks for Hook<'_> {
    fn post_force(&mut self, p: &mut Particles) {
        self.outside.apply(self.time, p);
    }
}

impl grains_dem3d::Hooks for Hook<'_, grains_dem3d::Particles> {
    fn post_force(&mut self, p: &mut grains_dem3d::Particles) {
        self.outside.apply(self.time, p);
    }
}
