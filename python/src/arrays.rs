//! Between numpy arrays and the engines' vectors: copies out, checked reads in (a wrong
//! dtype or shape is a `ValueError` naming the array and both shapes).

use glam::{DVec2, DVec3};
use numpy::{PyArray1, PyArrayDescrMethods, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// A per-particle value handed to numpy as one row of `WIDTH` float64 (a scalar: one
/// number, shape (N,)), laid out in memory as exactly those numbers, so a `Vec` of them
/// becomes an array without a copy.
///
/// # Safety
/// The type is `WIDTH` `f64`s with `f64`'s alignment and nothing else.
pub unsafe trait Row: Copy + Send + 'static {
    /// Numbers per value.
    const WIDTH: usize;
    /// Whether numpy shows one value per particle as a scalar (shape (N,)) rather than a
    /// row (shape (N, WIDTH)).
    const SCALAR: bool;
    /// The value from a row of `WIDTH` numbers.
    fn from_row(r: &[f64]) -> Self;
    /// The shape of `n` values.
    fn shape(n: usize) -> Vec<usize> {
        if Self::SCALAR {
            vec![n]
        } else {
            vec![n, Self::WIDTH]
        }
    }
}

// SAFETY: one f64.
unsafe impl Row for f64 {
    const WIDTH: usize = 1;
    const SCALAR: bool = true;
    fn from_row(r: &[f64]) -> Self {
        r[0]
    }
}

// SAFETY: glam's DVec2 and DVec3 are #[repr(C)] structs of 2 and 3 f64 (checked below).
unsafe impl Row for DVec2 {
    const WIDTH: usize = 2;
    const SCALAR: bool = false;
    fn from_row(r: &[f64]) -> Self {
        DVec2::new(r[0], r[1])
    }
}

// SAFETY: as DVec2's.
unsafe impl Row for DVec3 {
    const WIDTH: usize = 3;
    const SCALAR: bool = false;
    fn from_row(r: &[f64]) -> Self {
        DVec3::new(r[0], r[1], r[2])
    }
}

const _: () = assert!(std::mem::size_of::<DVec2>() == 16 && std::mem::align_of::<DVec2>() == 8);
const _: () = assert!(std::mem::size_of::<DVec3>() == 24 && std::mem::align_of::<DVec3>() == 8);

/// An (N, WIDTH) (or (N,)) float64 array, copied from `v`.
pub fn rows<'py, V: Row>(py: Python<'py>, v: &[V]) -> Bound<'py, PyAny> {
    rows_owned(py, v.to_vec())
}

/// An (N, WIDTH) (or (N,)) float64 array, taking `v` without a copy.
pub fn rows_owned<V: Row>(py: Python<'_>, v: Vec<V>) -> Bound<'_, PyAny> {
    let (n, w) = (v.len(), V::WIDTH);
    let mut v = std::mem::ManuallyDrop::new(v);
    // SAFETY: `Row` says a V is W f64 with f64's alignment, so N of them are W N f64 in
    // the same allocation (capacity likewise).
    let flat = unsafe { Vec::from_raw_parts(v.as_mut_ptr() as *mut f64, w * n, w * v.capacity()) };
    let a = PyArray1::from_vec(py, flat);
    if V::SCALAR {
        return a.into_any();
    }
    a.reshape([n, w])
        .expect("W N values make N rows of W")
        .into_any()
}

/// An (N,) float64 array, taking `v`.
pub fn scalars(py: Python<'_>, v: Vec<f64>) -> Bound<'_, PyAny> {
    rows_owned(py, v)
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

/// Reads `obj` as `n` values `V` (an (n, WIDTH) or (n,) float64 array) named `what` for
/// `call`.
pub fn read_rows<V: Row>(
    obj: &Bound<'_, PyAny>,
    call: &str,
    what: &str,
    n: usize,
) -> PyResult<Vec<V>> {
    let a = as_array(obj)?;
    if !a.dtype().is_equiv_to(&numpy::dtype::<f64>(obj.py())) {
        return Err(PyValueError::new_err(format!(
            "{call}: {what} has dtype {}, expected float64",
            a.dtype()
        )));
    }
    let want = V::shape(n);
    if a.shape() != want.as_slice() {
        return Err(PyValueError::new_err(format!(
            "{call}: {what} has shape {}, expected {}",
            shown(a.shape()),
            shown(&want)
        )));
    }
    let flat = obj
        .py()
        .import("numpy")?
        .call_method1("ravel", (a,))?
        .cast_into::<PyArray1<f64>>()?
        .to_vec()?;
    Ok(flat.chunks_exact(V::WIDTH).map(V::from_row).collect())
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
