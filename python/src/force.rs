//! A Python callable as an outside force: `fn(sim)` is called inside each step, after the
//! contact forces are summed, with `sim` showing the particles as they are at that point
//! (positions at the end of the step, velocities at the half step); it returns an
//! (N, dim) float64 array of forces in id order, or a tuple (forces, torques) with
//! torques an (N,) array in 2D and an (N, 3) array in 3D.

use crate::arrays::{read_rows, Row};
use crate::sim::{InStep, Simulation, Snapshot};
use grains_sim::forces::{ForceError, OutsideForce};
use grains_sim::session::data::{IdOrder, ParticleData};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use std::ops::AddAssign;
use std::sync::Arc;

/// A force callback and (weakly) the simulation it is given.
pub struct PyForce {
    /// The callable.
    pub func: Py<PyAny>,
    /// A weak reference to the `grains.Simulation`.
    pub sim: Py<PyAny>,
}

impl PyForce {
    /// Calls the callable with the particles `data` (in id order) showing, and reads
    /// back its forces `V` and optional torques `A`, `n` of each.
    fn call<V: Row, A: Row>(
        &self,
        py: Python<'_>,
        data: Snapshot,
        n: usize,
        time: f64,
    ) -> PyResult<(Vec<V>, Option<Vec<A>>)> {
        let sim = self.sim.bind(py).call0()?;
        let sim = sim.cast::<Simulation>()?;
        sim.get().enter(InStep {
            particles: data,
            time,
        });
        let r = self.func.bind(py).call1((sim,));
        sim.get().leave();
        let r = r?;
        let call = "add_force callback";
        match r.cast::<PyTuple>() {
            Ok(tup) if tup.len() == 2 => Ok((
                read_rows(&tup.get_item(0)?, call, "force", n)?,
                Some(read_rows(&tup.get_item(1)?, call, "torque", n)?),
            )),
            _ => Ok((read_rows(&r, call, "force", n)?, None)),
        }
    }
}

/// Adds forces `f` and torques `t` (id order) to the particles stored with ids `id`.
fn add<V: AddAssign + Copy, A: AddAssign + Copy>(
    id: &[u32],
    force: &mut [V],
    torque: &mut [A],
    (f, t): (Vec<V>, Option<Vec<A>>),
) {
    IdOrder::of(id).each(id, |i, k| {
        force[i] += f[k];
        if let Some(t) = &t {
            torque[i] += t[k];
        }
    });
}

impl OutsideForce for PyForce {
    fn add(&mut self, time: f64, p: &mut grains_dem::Particles) -> Result<(), ForceError> {
        Python::attach(|py| -> PyResult<()> {
            let data = Snapshot::Two(Arc::new(ParticleData::of_dem(p)));
            let got = self.call(py, data, p.len(), time)?;
            add(&p.id, &mut p.force, &mut p.torque, got);
            Ok(())
        })
        .map_err(|e| Box::new(e) as ForceError)
    }
}

impl OutsideForce<grains_dem3d::Particles> for PyForce {
    fn add(&mut self, time: f64, p: &mut grains_dem3d::Particles) -> Result<(), ForceError> {
        Python::attach(|py| -> PyResult<()> {
            let data = Snapshot::Three(Arc::new(
                grains_sim::session::data::ParticleData3::of_dem3(p),
            ));
            let got = self.call(py, data, p.len(), time)?;
            add(&p.id, &mut p.force, &mut p.torque, got);
            Ok(())
        })
        .map_err(|e| Box::new(e) as ForceError)
    }
}
