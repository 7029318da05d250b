//! A Python callable as an outside force: `fn(sim)` is called inside each step, after the
//! contact forces are summed, with `sim` showing the particles as they are at that point
//! (positions at the end of the step, velocities at the half step); it returns an
//! (N, 2) float64 array of forces in id order, or a tuple (forces, torques) with torques
//! an (N,) array.

use crate::arrays::{read_scalars, read_vec2};
use crate::sim::{InStep, Simulation};
use grains_sim::forces::{ForceError, OutsideForce};
use grains_sim::session::data::{IdOrder, ParticleData};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use std::sync::Arc;

/// A force callback and (weakly) the simulation it is given.
pub struct PyForce {
    /// The callable.
    pub func: Py<PyAny>,
    /// A weak reference to the `grains.Simulation`.
    pub sim: Py<PyAny>,
}

impl OutsideForce for PyForce {
    fn add(&mut self, time: f64, p: &mut grains_dem::Particles) -> Result<(), ForceError> {
        Python::attach(|py| -> PyResult<()> {
            let sim = self.sim.bind(py).call0()?;
            let sim = sim.cast::<Simulation>()?;
            let snapshot = Arc::new(ParticleData::of_dem(p));
            let n = snapshot.id.len();
            sim.get().enter(InStep {
                particles: snapshot,
                time,
            });
            let r = self.func.bind(py).call1((sim,));
            sim.get().leave();
            let r = r?;
            let call = "add_force callback";
            let (f, t) = match r.cast::<PyTuple>() {
                Ok(tup) if tup.len() == 2 => (
                    read_vec2(&tup.get_item(0)?, call, "force", n)?,
                    Some(read_scalars(&tup.get_item(1)?, call, "torque", n)?),
                ),
                _ => (read_vec2(&r, call, "force", n)?, None),
            };
            IdOrder::of(&p.id).each(&p.id, |i, k| {
                p.force[i] += f[k];
                if let Some(t) = &t {
                    p.torque[i] += t[k];
                }
            });
            Ok(())
        })
        .map_err(|e| Box::new(e) as ForceError)
    }
}
