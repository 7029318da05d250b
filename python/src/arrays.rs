//! Between numpy arrays and the engines' vectors: copies out, checked reads in (a wrong
//! dtype or shape is a `ValueError` naming the array and both shapes).

use glam::DVec2;
use numpy::{PyArray1, PyArrayDescrMethods, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// An (N, 2) float64 array, copied from `v`.
pub fn vec2<'py>(py: Python<'py>, v: &[DVec2]) -> Bound<'py, PyAny> {
    vec2_owned(py, v.to_vec())
}

// What `vec2_owned` relies on.
const _: () = assert!(std::mem::size_of::<DVec2>() == 16 && std::mem::align_of::<DVec2>() == 8);

/// An (N, 2) float64 array, taking `v` without a copy.
pub fn vec2_owned(py: Python<'_>, v: Vec<DVec2>) -> Bound<'_, PyAny> {
    let n = v.len();
    let mut v = std::mem::ManuallyDrop::new(v);
    // SAFETY: DVec2 is #[repr(C)] { x: f64, y: f64 }: two f64 with f64's alignment, so N
    // of them are 2N f64 in the same allocation (capacity likewise).
    let flat = unsafe { Vec::from_raw_parts(v.as_mut_ptr() as *mut f64, 2 * n, 2 * v.capacity()) };
    PyArray1::from_vec(py, flat)
        .reshape([n, 2])
        .expect("2N values make N rows of 2")
        .into_any()
}

/// An (N,) float64 array, taking `v`.
pub fn scalars(py: Python<'_>, v: Vec<f64>) -> Bound<'_, PyAny> {
    PyArray1::from_vec(py, v).into_any()
}

/// An (N,) uint32 array, taking `v`.
pub fn ids(py: Python<'_>, v: Vec<u32>) -> Bound<'_, PyAny> {
    PyArray1::from_vec(py, v).into_any()
}

/// Shape as Python prints it.
fn shown(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(|n| n.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// `obj` as a numpy array: an array as it is (its dtype is checked by the caller), any
/// other sequence converted as float64.
fn as_array<'py>(obj: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyUntypedArray>> {
    if let Ok(a) = obj.cast::<PyUntypedArray>() {
        return Ok(a.clone());
    }
    let np = obj.py().import("numpy")?;
    let a = np.call_method1("asarray", (obj, "float64"))?;
    Ok(a.cast_into::<PyUntypedArray>()?)
}

/// Reads `obj` as an (n, 2) float64 array named `what` for `call`.
pub fn read_vec2(obj: &Bound<'_, PyAny>, call: &str, what: &str, n: usize) -> PyResult<Vec<DVec2>> {
    let a = as_array(obj)?;
    if !a.dtype().is_equiv_to(&numpy::dtype::<f64>(obj.py())) {
        return Err(PyValueError::new_err(format!(
            "{call}: {what} has dtype {}, expected float64",
            a.dtype()
        )));
    }
    if a.shape() != [n, 2] {
        return Err(PyValueError::new_err(format!(
            "{call}: {what} has shape {}, expected {}",
            shown(a.shape()),
            shown(&[n, 2])
        )));
    }
    let a = a.cast::<numpy::PyArray2<f64>>()?;
    let r = a.readonly();
    let view = r.as_array();
    Ok(view
        .rows()
        .into_iter()
        .map(|row| DVec2::new(row[0], row[1]))
        .collect())
}

/// Reads `obj` as an (n,) float64 array named `what` for `call`.
pub fn read_scalars(
    obj: &Bound<'_, PyAny>,
    call: &str,
    what: &str,
    n: usize,
) -> PyResult<Vec<f64>> {
    let a = as_array(obj)?;
    if !a.dtype().is_equiv_to(&numpy::dtype::<f64>(obj.py())) {
        return Err(PyValueError::new_err(format!(
            "{call}: {what} has dtype {}, expected float64",
            a.dtype()
        )));
    }
    if a.shape() != [n] {
        return Err(PyValueError::new_err(format!(
            "{call}: {what} has shape {}, expected {}",
            shown(a.shape()),
            shown(&[n])
        )));
    }
    Ok(a.cast::<PyArray1<f64>>()?.to_vec()?)
}

/// Reads `obj` as a one-dimensional array of particle ids named `what` for `call`.
pub fn read_ids(obj: &Bound<'_, PyAny>, call: &str, what: &str) -> PyResult<Vec<u32>> {
    let np = obj.py().import("numpy")?;
    let a = np.call_method1("asarray", (obj,))?;
    let a = a.cast::<PyUntypedArray>()?;
    let kind: String = a.dtype().getattr("kind")?.extract()?;
    if !(kind == "i" || kind == "u") && a.len() > 0 {
        return Err(PyValueError::new_err(format!(
            "{call}: {what} has dtype {}, expected integers",
            a.dtype()
        )));
    }
    if a.ndim() != 1 {
        return Err(PyValueError::new_err(format!(
            "{call}: {what} has shape {}, expected (k,)",
            shown(a.shape())
        )));
    }
    let a = np.call_method1("asarray", (a, "int64"))?;
    let v: Vec<i64> = a.cast::<PyArray1<i64>>()?.to_vec()?;
    v.into_iter()
        .map(|k| {
            u32::try_from(k).map_err(|_| {
                PyValueError::new_err(format!("{call}: {what} holds {k}, not a particle id"))
            })
        })
        .collect()
}
