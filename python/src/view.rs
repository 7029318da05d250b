//! `grains.View`: a read-only, zero-copy numpy array over one particle field as the
//! engine stores it. The engine re-sorts its particles at neighbour-list rebuilds, so a
//! view remembers the storage's layout counter when it was made and raises
//! `StaleViewError` once it has changed. An array `np.asarray(view)` gives points into
//! the engine's memory, so while one (or a slice of it) is referenced the simulation
//! refuses to step: keep the view, not the array.

use crate::sim::Simulation;
use crate::StaleViewError;
use grains_sim::session::data::Field;
use numpy::ndarray::{ArrayView1, ArrayView2};
use numpy::{PyArray1, PyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// What every array a view hands out (and every numpy view of it) names as its base: while
/// one lives, its weak reference in the simulation says so and stepping is refused.
#[pyclass(module = "grains", frozen, weakref)]
pub struct Guard {
    _sim: Py<Simulation>,
}

/// A read-only zero-copy view of a particle field (storage order).
#[pyclass(module = "grains", frozen)]
pub struct View {
    sim: Py<Simulation>,
    name: String,
    layout: u64,
    len: usize,
}

impl View {
    /// The view of field `name` of `sim`.
    pub fn new(sim: &Bound<'_, Simulation>, name: &str) -> PyResult<Self> {
        let s = sim.get().locked()?;
        let field = s.field(name).ok_or_else(|| {
            PyValueError::new_err(format!(
                "view: name = {name:?}: not a field of this {} run (DEM in 2D and 3D, and FEM–DEM: id, position, velocity, omega, radius, force; MPM: id, position, velocity, mass)",
                s.engine()
            ))
        })?;
        Ok(View {
            sim: sim.clone().unbind(),
            name: name.to_string(),
            layout: s.layout(),
            len: len(field),
        })
    }
}

fn len(f: Field<'_>) -> usize {
    match f {
        Field::Ids(v) => v.len(),
        Field::Scalar(v) => v.len(),
        Field::Vector(v) => v.len(),
        Field::Vector3(v) => v.len(),
    }
}

#[pymethods]
impl View {
    /// The zero-copy array (read-only); raises StaleViewError once the storage changed.
    #[getter]
    fn array<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        let me = slf.get();
        let py = slf.py();
        let sim = me.sim.bind(py).get();
        let s = sim.locked()?;
        let field = s.field(&me.name).filter(|f| len(*f) == me.len);
        let (Some(field), true) = (field, s.layout() == me.layout) else {
            return Err(StaleViewError::new_err(format!(
                "view({:?}): the engine has reordered its particles since the view was made (a neighbour-list rebuild); take a new view",
                me.name
            )));
        };
        let owner = Bound::new(
            py,
            Guard {
                _sim: me.sim.clone_ref(py),
            },
        )?;
        sim.hand_out(&owner)?;
        let owner = owner.into_any();
        // SAFETY: the slices belong to the session, which `owner` (holding the
        // simulation) keeps alive; the layout check above says they have not been
        // reallocated since the view was made, and the simulation refuses to step (the
        // only thing that moves them) while `owner` lives. The array is read-only.
        let a = unsafe {
            match field {
                Field::Ids(v) => {
                    let a = ArrayView1::from_shape_ptr(v.len(), v.as_ptr());
                    PyArray1::borrow_from_array(&a, owner).into_any()
                }
                Field::Scalar(v) => {
                    let a = ArrayView1::from_shape_ptr(v.len(), v.as_ptr());
                    PyArray1::borrow_from_array(&a, owner).into_any()
                }
                Field::Vector(v) => {
                    let a = ArrayView2::from_shape_ptr((v.len(), 2), v.as_ptr() as *const f64);
                    PyArray2::borrow_from_array(&a, owner).into_any()
                }
                Field::Vector3(v) => {
                    let a = ArrayView2::from_shape_ptr((v.len(), 3), v.as_ptr() as *const f64);
                    PyArray2::borrow_from_array(&a, owner).into_any()
                }
            }
        };
        a.getattr("flags")?.setattr("writeable", false)?;
        Ok(a)
    }

    #[pyo3(signature = (dtype=None, copy=None))]
    fn __array__<'py>(
        slf: &Bound<'py, Self>,
        dtype: Option<Bound<'py, PyAny>>,
        copy: Option<bool>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let mut a = Self::array(slf)?;
        if let Some(d) = dtype {
            a = a.call_method1("astype", (d,))?;
        }
        if copy == Some(true) {
            a = a.call_method0("copy")?;
        }
        Ok(a)
    }

    /// Indexing reads through the view (and copies what it reads).
    fn __getitem__<'py>(
        slf: &Bound<'py, Self>,
        key: Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let a = Self::array(slf)?.get_item(key)?;
        match a.hasattr("copy")? {
            true => a.call_method0("copy"),
            false => Ok(a),
        }
    }

    fn __len__(&self) -> usize {
        self.len
    }

    /// Whether the view still shows the engine's storage.
    #[getter]
    fn valid(&self, py: Python<'_>) -> PyResult<bool> {
        let s = self.sim.bind(py).get().locked()?;
        Ok(s.layout() == self.layout && s.field(&self.name).is_some_and(|f| len(f) == self.len))
    }

    /// The field's name.
    #[getter]
    fn name(&self) -> &str {
        &self.name
    }
}
