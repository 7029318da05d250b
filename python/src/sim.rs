//! `grains.Simulation`: one handle on a run of any engine (a `Session`), stepped with
//! the GIL released and Ctrl-C checked between steps.

use crate::arrays::{ids, read_ids, read_rows, rows, rows_owned, scalars, Row};
use crate::{from_json, guarded, panic_message, InputError, InternalError};
use glam::{DVec2, DVec3};
use grains_sim::session::data::{Contacts, ParticleData, ParticleData3};
use grains_sim::session::{self, Session};
use grains_sim::Status;
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::panic::AssertUnwindSafe;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, TryLockError};
use std::time::Instant;

/// The particles in id order, of a 2D or a 3D run.
#[derive(Clone)]
pub enum Snapshot {
    /// Disks (or MPM points).
    Two(Arc<ParticleData>),
    /// Spheres.
    Three(Arc<ParticleData3>),
}

/// What a force callback sees of the run, mid-step.
pub struct InStep {
    /// The particles in id order.
    pub particles: Snapshot,
    /// The time at the end of the step being taken (s).
    pub time: f64,
}

/// A simulation of any engine (DEM in 2D or 3D, MPM, FEM–DEM), opened from a scenario.
#[pyclass(module = "grains", frozen, weakref)]
pub struct Simulation {
    inner: Mutex<Session>,
    /// Spatial dimensions (fixed for a run).
    dim: usize,
    in_step: Mutex<Option<InStep>>,
    broken: AtomicBool,
    /// Weak references to the owners of the arrays views handed out.
    handed_out: Mutex<Vec<Py<PyAny>>>,
    /// Steps per chunk between signal checks, learnt across calls: a run with a callback
    /// every few steps would otherwise start again at one step each time.
    chunk: AtomicU64,
}

/// The particles in id order (copies); fields the engine has not are None. 2D runs:
/// vectors (N, 2), spins and torques (N,); 3D runs: all (N, 3).
#[pyclass(module = "grains", frozen, get_all)]
pub struct Particles {
    /// Ids (N,), uint32.
    pub id: Py<PyAny>,
    /// Positions (N, dim), m.
    pub position: Py<PyAny>,
    /// Velocities (N, dim), m/s.
    pub velocity: Py<PyAny>,
    /// Angular velocities, rad/s: (N,) in 2D, (N, 3) in 3D (None for MPM points).
    pub omega: Py<PyAny>,
    /// Radii (N,), m.
    pub radius: Py<PyAny>,
    /// Masses (N,): kg/m in 2D, kg in 3D.
    pub mass: Py<PyAny>,
    /// Forces at the last evaluation (N, dim): N/m in 2D, N in 3D (None for MPM points).
    pub force: Py<PyAny>,
    /// Torques at the last evaluation: (N,) N in 2D, (N, 3) N m in 3D (None for MPM
    /// points).
    pub torque: Py<PyAny>,
}

#[pymethods]
impl Particles {
    fn __len__(&self, py: Python<'_>) -> PyResult<usize> {
        self.id.bind(py).len()
    }
}

pub(crate) fn to_py(e: session::Error) -> PyErr {
    match e {
        session::Error::Input(m) => InputError::new_err(m),
        session::Error::Argument(m) => PyValueError::new_err(m),
        session::Error::Force(b) => match b.downcast::<PyErr>() {
            Ok(e) => *e,
            Err(b) => PyRuntimeError::new_err(b.to_string()),
        },
        e @ session::Error::Ended => PyRuntimeError::new_err(e.to_string()),
        session::Error::Output(e) => PyOSError::new_err(format!("{e:#}")),
    }
}

fn particles_object<V: Row, A: Row>(py: Python<'_>, p: ParticleData<V, A>) -> Particles {
    let opt = |v: Option<Bound<'_, PyAny>>| v.map_or_else(|| py.None(), |b| b.unbind());
    Particles {
        id: ids(py, p.id).unbind(),
        position: rows_owned(py, p.pos).unbind(),
        velocity: rows_owned(py, p.vel).unbind(),
        omega: opt(p.omega.map(|v| rows_owned(py, v))),
        radius: scalars(py, p.radius).unbind(),
        mass: scalars(py, p.mass).unbind(),
        force: opt(p.force.map(|v| rows_owned(py, v))),
        torque: opt(p.torque.map(|v| rows_owned(py, v))),
    }
}

/// The contacts as a dict of arrays.
fn contacts_dict<V: Row>(py: Python<'_>, c: Contacts<V>) -> PyResult<Py<PyDict>> {
    let d = PyDict::new(py);
    d.set_item("i", ids(py, c.i))?;
    d.set_item("j", ids(py, c.j))?;
    d.set_item("overlap", scalars(py, c.overlap))?;
    d.set_item("normal_force", rows_owned(py, c.normal_force))?;
    d.set_item("tangential_force", rows_owned(py, c.tangential_force))?;
    d.set_item("branch", rows_owned(py, c.branch))?;
    Ok(d.unbind())
}

/// A Python dict (of TOML-able values) as a TOML table.
fn to_toml(v: &Bound<'_, PyAny>, key: &str) -> PyResult<toml::Value> {
    use pyo3::types::{PyBool, PyFloat, PyInt, PyString, PyTuple};
    if v.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(v.extract()?));
    }
    if v.is_instance_of::<PyInt>() {
        return Ok(toml::Value::Integer(v.extract()?));
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(v.extract()?));
    }
    if v.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(v.extract()?));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut t = toml::Table::new();
        for (k, x) in d.iter() {
            let k: String = k
                .extract()
                .map_err(|_| InputError::new_err(format!("{key}: keys must be strings")))?;
            let sub = if key.is_empty() {
                k.clone()
            } else {
                format!("{key}.{k}")
            };
            t.insert(k, to_toml(&x, &sub)?);
        }
        return Ok(toml::Value::Table(t));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() || v.hasattr("tolist")? {
        let list = if v.hasattr("tolist")? {
            v.call_method0("tolist")?
        } else {
            v.clone()
        };
        let mut a = Vec::new();
        for (k, x) in list.try_iter()?.enumerate() {
            a.push(to_toml(&x?, &format!("{key}[{k}]"))?);
        }
        return Ok(toml::Value::Array(a));
    }
    if let Ok(x) = v.extract::<f64>() {
        return Ok(toml::Value::Float(x));
    }
    Err(InputError::new_err(format!(
        "{key} = {}: not a TOML value (use numbers, strings, booleans, lists and dicts)",
        v.repr()?
    )))
}

impl Simulation {
    fn wrap(s: Session) -> Self {
        Simulation {
            dim: s.dim(),
            inner: Mutex::new(s),
            in_step: Mutex::new(None),
            broken: AtomicBool::new(false),
            handed_out: Mutex::new(Vec::new()),
            chunk: AtomicU64::new(1),
        }
    }

    /// The session, unless it is stepping (inside a force callback) or broke.
    fn session(&self) -> PyResult<MutexGuard<'_, Session>> {
        if self.broken.load(Ordering::Relaxed) {
            return Err(InternalError::new_err(
                "an earlier call on this simulation panicked; its state is unknown: open the scenario again",
            ));
        }
        match self.inner.try_lock() {
            Ok(g) => Ok(g),
            Err(TryLockError::WouldBlock) => Err(PyRuntimeError::new_err(
                "the simulation is stepping: inside a force callback only sim.particles(), sim.time and sim.dim can be read",
            )),
            Err(TryLockError::Poisoned(_)) => {
                self.broken.store(true, Ordering::Relaxed);
                Err(InternalError::new_err("an earlier call on this simulation panicked"))
            }
        }
    }

    /// Runs `f` on the session, a panic becoming `InternalError` (and the simulation
    /// unusable).
    fn with<T>(&self, f: impl FnOnce(&mut Session) -> PyResult<T>) -> PyResult<T> {
        let mut g = self.session()?;
        match std::panic::catch_unwind(AssertUnwindSafe(|| f(&mut g))) {
            Ok(r) => r,
            Err(p) => {
                self.broken.store(true, Ordering::Relaxed);
                Err(InternalError::new_err(panic_message(&*p)))
            }
        }
    }

    /// Records the owner of an array a view hands out.
    pub fn hand_out(&self, owner: &Bound<'_, PyAny>) -> PyResult<()> {
        let weak = owner
            .py()
            .import("weakref")?
            .call_method1("ref", (owner,))?;
        let mut list = self.handed_out.lock().unwrap_or_else(|e| e.into_inner());
        if list.len() >= 256 {
            // Many views read without a step between: forget the arrays already gone.
            list.retain(|w| w.bind(owner.py()).call0().is_ok_and(|o| !o.is_none()));
        }
        list.push(weak.unbind());
        Ok(())
    }

    /// Refuses to go on while an array handed out by a view is referenced: the step may
    /// move the memory it points into.
    fn no_arrays_out(&self, py: Python<'_>) -> PyResult<()> {
        let mut list = self.handed_out.lock().unwrap_or_else(|e| e.into_inner());
        let mut live = Vec::new();
        for w in list.drain(..) {
            if !w.bind(py).call0()?.is_none() {
                live.push(w);
            }
        }
        let n = live.len();
        *list = live;
        if n > 0 {
            return Err(PyRuntimeError::new_err(format!(
                "{n} array(s) taken from sim.view(...) (np.asarray(view), view.array, or slices of them) are still referenced; the step may move the memory they show: delete them, or copy what you keep, before stepping (the View objects themselves may stay)"
            )));
        }
        Ok(())
    }

    /// Enters a force callback: reads see `s`.
    pub fn enter(&self, s: InStep) {
        *self.in_step.lock().unwrap_or_else(|e| e.into_inner()) = Some(s);
    }

    /// Leaves a force callback.
    pub fn leave(&self) {
        *self.in_step.lock().unwrap_or_else(|e| e.into_inner()) = None;
    }

    fn in_step<T>(&self, f: impl FnOnce(&InStep) -> T) -> Option<T> {
        self.in_step
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .as_ref()
            .map(f)
    }

    /// Steps up to `n` steps (to `until` or the end when `to_end`), the GIL released, in
    /// chunks between which Ctrl-C is checked; a stop status when the run stopped.
    fn advance(
        &self,
        py: Python<'_>,
        n: u64,
        until: Option<f64>,
        to_end: bool,
        stop_at_rule: bool,
    ) -> PyResult<Option<Status>> {
        self.no_arrays_out(py)?;
        let mut left = n;
        let mut chunk = self.chunk.load(Ordering::Relaxed);
        while left > 0 {
            let k = chunk.min(left);
            let started = Instant::now();
            let (stop, taken) = self.with(|s| {
                let before = s.clock().step;
                let r = py.detach(|| {
                    s.step_while(k, stop_at_rule, |c, over| {
                        !to_end || session::wanted(c, over, until)
                    })
                });
                Ok((r.map_err(to_py)?, s.clock().step - before))
            })?;
            if stop.is_some() || taken < k {
                return Ok(stop);
            }
            left -= k;
            py.check_signals()?;
            // Chunks of 20 to 80 ms: Ctrl-C answers quickly, the checks cost nothing.
            // Only a full chunk says how long one takes.
            if k == chunk {
                let took = started.elapsed().as_secs_f64();
                if took < 0.02 {
                    chunk = chunk.saturating_mul(2);
                } else if took > 0.08 && chunk > 1 {
                    chunk /= 2;
                }
                self.chunk.store(chunk, Ordering::Relaxed);
            }
        }
        Ok(None)
    }
}

fn status_name(s: &Status) -> &'static str {
    s.name()
}

#[pymethods]
impl Simulation {
    /// Opens the scenario file `path` (DEM in 2D or 3D, MPM or FEM–DEM); raises
    /// InputError with the command line's one-line message when it is refused.
    #[staticmethod]
    fn from_file(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        guarded(|| {
            Ok(Self::wrap(
                py.detach(|| Session::from_file(&path)).map_err(to_py)?,
            ))
        })
    }

    /// Opens a scenario given as TOML text; relative paths in it start at `base`
    /// (default the current directory).
    #[staticmethod]
    #[pyo3(signature = (text, base=None))]
    fn from_toml(py: Python<'_>, text: &str, base: Option<PathBuf>) -> PyResult<Self> {
        let base = base.unwrap_or_else(|| PathBuf::from("."));
        guarded(|| {
            Ok(Self::wrap(
                py.detach(|| Session::from_toml(text, &base))
                    .map_err(to_py)?,
            ))
        })
    }

    /// Opens a scenario given as a dict (the TOML file's tables as dicts, arrays of
    /// tables as lists of dicts); relative paths start at `base`.
    #[staticmethod]
    #[pyo3(signature = (d, base=None))]
    fn from_dict(py: Python<'_>, d: &Bound<'_, PyDict>, base: Option<PathBuf>) -> PyResult<Self> {
        let base = base.unwrap_or_else(|| PathBuf::from("."));
        guarded(|| {
            let toml::Value::Table(t) = to_toml(d.as_any(), "")? else {
                return Err(InputError::new_err("from_dict: expects a dict"));
            };
            Ok(Self::wrap(
                py.detach(|| Session::from_table(&t, &base))
                    .map_err(to_py)?,
            ))
        })
    }

    /// Continues the run checkpointed in the directory `path` (by `checkpoint` or by
    /// `grains run`), bitwise as `grains resume` does.
    #[staticmethod]
    fn resume(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        guarded(|| {
            Ok(Self::wrap(
                py.detach(|| Session::resume(&path)).map_err(to_py)?,
            ))
        })
    }

    /// Takes `n` steps (past the scenario's end if asked).
    #[pyo3(signature = (n=1))]
    fn step(&self, py: Python<'_>, n: u64) -> PyResult<()> {
        guarded(|| {
            if let Some(Status::Unstable(m)) = self.advance(py, n, None, false, false)? {
                return Err(PyRuntimeError::new_err(format!(
                    "the run became unstable: {m}"
                )));
            }
            Ok(())
        })
    }

    /// Runs to the scenario's end, or to time `until` (s); `callback(sim)` every `every`
    /// steps. Returns how it ended: "completed", "at_rest", "unstable" or "paused"
    /// (stopped at `until`). Ctrl-C raises KeyboardInterrupt between steps and leaves a
    /// state that can be stepped or checkpointed.
    #[pyo3(signature = (until=None, callback=None, every=1))]
    fn run(
        slf: &Bound<'_, Self>,
        until: Option<f64>,
        callback: Option<Bound<'_, PyAny>>,
        every: u64,
    ) -> PyResult<&'static str> {
        let py = slf.py();
        let me = slf.get();
        if every == 0 {
            return Err(PyValueError::new_err("run: every = 0: must be at least 1"));
        }
        guarded(|| loop {
            let block = if callback.is_some() { every } else { u64::MAX };
            if let Some(s) = me.advance(py, block, until, true, true)? {
                return Ok(status_name(&s));
            }
            let (wanted, at_end) = me.with(|s| {
                let at_end = s.at_end();
                Ok((session::wanted(s.clock(), at_end, until), at_end))
            })?;
            if let Some(cb) = &callback {
                if wanted {
                    cb.call1((slf,))?;
                }
            }
            if !wanted {
                return Ok(if at_end { "completed" } else { "paused" });
            }
        })
    }

    /// Simulated time (s).
    #[getter]
    fn time(&self) -> PyResult<f64> {
        if let Some(t) = self.in_step(|s| s.time) {
            return Ok(t);
        }
        self.with(|s| Ok(s.clock().time))
    }

    /// Steps taken.
    #[getter]
    fn steps(&self) -> PyResult<u64> {
        self.with(|s| Ok(s.clock().step))
    }

    /// The time step (s); FEM–DEM runs adapt it (the last one taken).
    #[getter]
    fn dt(&self) -> PyResult<f64> {
        self.with(|s| Ok(s.dt()))
    }

    /// "dem", "mpm" or "fem_dem".
    #[getter]
    fn engine(&self) -> PyResult<&'static str> {
        self.with(|s| Ok(s.engine()))
    }

    /// Spatial dimensions: 2, or 3 for a 3D DEM run.
    #[getter]
    fn dim(&self) -> usize {
        self.dim
    }

    /// How the run's own rules stopped it ("at_rest", "unstable"), or None.
    #[getter]
    fn status(&self) -> PyResult<Option<&'static str>> {
        self.with(|s| Ok(s.stopped().map(status_name)))
    }

    /// The directory the run writes into as it goes (temporary).
    #[getter]
    fn work_dir(&self) -> PyResult<PathBuf> {
        self.with(|s| Ok(s.work_dir().to_path_buf()))
    }

    /// The fingerprint of the whole state, as `summary.json`'s `state_hash` (hex).
    fn state_hash(&self) -> PyResult<String> {
        self.with(|s| Ok(format!("{:016x}", s.state_hash())))
    }

    /// The particles in id order (copies): DEM disks or spheres, a FEM–DEM run's ring,
    /// MPM points.
    fn particles(&self, py: Python<'_>) -> PyResult<Particles> {
        guarded(|| {
            if let Some(p) = self.in_step(|s| s.particles.clone()) {
                return Ok(match p {
                    Snapshot::Two(p) => particles_object(py, (*p).clone()),
                    Snapshot::Three(p) => particles_object(py, (*p).clone()),
                });
            }
            if self.dim == 3 {
                let p = self.with(|s| Ok(py.detach(move || s.particles3())))?;
                return Ok(particles_object(py, p.unwrap_or_default()));
            }
            let p = self.with(|s| Ok(py.detach(move || s.particles())))?;
            Ok(particles_object(py, p))
        })
    }

    /// A read-only zero-copy view of the particle field `name` ("id", "position",
    /// "velocity", "omega", "radius", "force"; MPM: "id", "position", "velocity",
    /// "mass") in the engine's storage order (the "id" view names the rows); it raises
    /// StaleViewError once the engine reorders or resizes its storage.
    fn view(slf: &Bound<'_, Self>, name: &str) -> PyResult<crate::view::View> {
        crate::view::View::new(slf, name)
    }

    /// Sets "position" or "velocity" of the particles `ids` to `values`, (k, dim)
    /// float64.
    fn set(&self, name: &str, ids: &Bound<'_, PyAny>, values: &Bound<'_, PyAny>) -> PyResult<()> {
        guarded(|| {
            let call = format!("set({name:?})");
            let ids = read_ids(ids, &call, "ids")?;
            let k = ids.len();
            if self.dim == 3 {
                let v = read_rows::<DVec3>(values, &call, "values", k)?;
                return self.with(|s| s.set3(name, &ids, &v).map_err(to_py));
            }
            let v = read_rows::<DVec2>(values, &call, "values", k)?;
            self.with(|s| s.set(name, &ids, &v).map_err(to_py))
        })
    }

    /// Adds a force callback (DEM and FEM–DEM runs): `fn(sim)` returns an (N, dim)
    /// float64 array of forces in id order (or a tuple with torques: (N,) in 2D, (N, 3)
    /// in 3D), added to the particles in every step after the contact forces are summed.
    fn add_force(slf: &Bound<'_, Self>, func: Bound<'_, PyAny>) -> PyResult<()> {
        let py = slf.py();
        let weak = py.import("weakref")?.call_method1("ref", (slf,))?;
        let f = crate::force::PyForce {
            func: func.unbind(),
            sim: weak.unbind(),
        };
        let me = slf.get();
        guarded(|| {
            me.with(|s| {
                match me.dim {
                    3 => s.add_force3(Box::new(f)),
                    _ => s.add_force(Box::new(f)),
                }
                .map_err(to_py)
            })
        })
    }

    /// The touching pairs (DEM and FEM–DEM): a dict of arrays i, j (ids), overlap,
    /// normal_force and tangential_force (on i, (M, dim)), branch (from i to j,
    /// (M, dim)).
    fn contacts(&self, py: Python<'_>) -> PyResult<Py<PyDict>> {
        guarded(|| {
            if self.dim == 3 {
                let c = self.with(|s| Ok(s.contacts3()))?.unwrap_or_default();
                return contacts_dict(py, c);
            }
            let c = self.with(|s| Ok(s.contacts()))?.ok_or_else(|| {
                PyValueError::new_err("contacts(): an MPM run has no particle contacts")
            })?;
            contacts_dict(py, c)
        })
    }

    /// An MPM run's points: a dict of arrays id, body, position, velocity, mass, volume,
    /// stress ((N, 3): xx, yy, xy).
    fn points(&self, py: Python<'_>) -> PyResult<Py<PyDict>> {
        guarded(|| {
            let p = self.with(|s| Ok(s.points()))?.ok_or_else(|| {
                PyValueError::new_err("points(): only MPM runs have material points")
            })?;
            let d = PyDict::new(py);
            d.set_item("id", ids(py, p.id))?;
            d.set_item("body", ids(py, p.body.iter().map(|&b| b as u32).collect()))?;
            d.set_item("position", rows(py, &p.pos))?;
            d.set_item("velocity", rows(py, &p.vel))?;
            d.set_item("mass", scalars(py, p.mass))?;
            d.set_item("volume", scalars(py, p.volume))?;
            let flat: Vec<f64> = p.stress.iter().flatten().copied().collect();
            let n = p.stress.len();
            d.set_item(
                "stress",
                scalars(py, flat).call_method1("reshape", ((n, 3),))?,
            )?;
            Ok(d.unbind())
        })
    }

    /// A FEM–DEM run's charge: a dict with node position and velocity (M, 2), triangles
    /// (K, 3) and each triangle's pressure (K,).
    fn charge(&self, py: Python<'_>) -> PyResult<Py<PyDict>> {
        guarded(|| {
            let c = self.with(|s| Ok(s.charge()))?.ok_or_else(|| {
                PyValueError::new_err("charge(): only FEM–DEM runs have a charge")
            })?;
            let d = PyDict::new(py);
            d.set_item("position", rows(py, &c.node_pos))?;
            d.set_item("velocity", rows(py, &c.node_vel))?;
            let k = c.triangles.len();
            let flat: Vec<u32> = c.triangles.iter().flatten().copied().collect();
            d.set_item(
                "triangles",
                ids(py, flat).call_method1("reshape", ((k, 3),))?,
            )?;
            d.set_item("pressure", scalars(py, c.pressure))?;
            Ok(d.unbind())
        })
    }

    /// The history so far: a dict of columns, as history.csv.
    fn history(&self, py: Python<'_>) -> PyResult<Py<PyDict>> {
        guarded(|| {
            let (names, rows) = self.with(|s| {
                let h = s.history();
                Ok((h.columns().to_vec(), h.rows().to_vec()))
            })?;
            let d = PyDict::new(py);
            for (k, name) in names.iter().enumerate() {
                d.set_item(name, scalars(py, rows.iter().map(|r| r[k]).collect()))?;
            }
            Ok(d.unbind())
        })
    }

    /// Ends the run as `grains run` does at its end (last frame, plots, checks) and
    /// returns summary.json as a dict; the simulation cannot step afterwards.
    fn summary(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        guarded(|| {
            let v = self.with(|s| {
                let done = py.detach(|| s.finish().map(|d| serde_json::to_value(&d.summary)));
                done.map_err(to_py)?
                    .map_err(|e| InternalError::new_err(e.to_string()))
            })?;
            from_json(py, &v)
        })
    }

    /// Ends the run (as `summary`) and writes what `grains run` writes into `out`.
    fn write(&self, py: Python<'_>, out: PathBuf) -> PyResult<()> {
        guarded(|| self.with(|s| py.detach(|| s.write(&out)).map(|_| ()).map_err(to_py)))
    }

    /// Writes a checkpoint into the directory `path` (a run directory that
    /// `Simulation.resume` and `grains resume` continue bitwise); DEM (2D and 3D) and
    /// FEM–DEM.
    fn checkpoint(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        guarded(|| self.with(|s| py.detach(|| s.checkpoint(&path)).map_err(to_py)))
    }

    fn __repr__(&self) -> PyResult<String> {
        self.with(|s| {
            let c = s.clock();
            Ok(format!(
                "<grains.Simulation engine={} dim={} t={:.6e} s steps={}>",
                s.engine(),
                self.dim,
                c.time,
                c.step
            ))
        })
    }
}

impl Simulation {
    /// The session, for the view.
    pub fn locked(&self) -> PyResult<MutexGuard<'_, Session>> {
        self.session()
    }
}
