//! grains from Python: the module `grains`, over the library façade
//! ([`grains_sim::session::Session`]). Every call runs under `catch_unwind`: a Rust
//! panic becomes `grains.InternalError`, never an abort of the interpreter.

mod arrays;
mod force;
mod sim;
mod view;

use pyo3::create_exception;
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use std::panic::AssertUnwindSafe;
use std::path::PathBuf;

create_exception!(
    grains,
    InputError,
    PyValueError,
    "A scenario, spec or checkpoint was refused: one line naming the key, the value and what is allowed, as the command line says it."
);
create_exception!(
    grains,
    InternalError,
    PyRuntimeError,
    "A bug in grains (a Rust panic), with its message; the simulation it happened in cannot be used any more."
);
create_exception!(
    grains,
    StaleViewError,
    PyRuntimeError,
    "A view used after the engine reordered or resized its particle storage; take a new one."
);

/// Runs `f`, turning a panic into `InternalError`.
pub(crate) fn guarded<T>(f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match std::panic::catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(p) => Err(InternalError::new_err(panic_message(&*p))),
    }
}

/// The message a panic carried.
pub(crate) fn panic_message(p: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        s.to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "a Rust panic without a message".into()
    }
}

/// A JSON value as Python objects (through `json.loads`).
pub(crate) fn from_json(py: Python<'_>, v: &serde_json::Value) -> PyResult<Py<PyAny>> {
    let text = serde_json::to_string(v).map_err(|e| InternalError::new_err(e.to_string()))?;
    Ok(py.import("json")?.call_method1("loads", (text,))?.unbind())
}

/// Runs the scenario at `path` as `grains run` does, writing into `out` (default
/// `runs/<name>`), on `threads` threads; returns the summary as a dict.
#[pyfunction]
#[pyo3(signature = (path, out=None, threads=None))]
fn run(
    py: Python<'_>,
    path: PathBuf,
    out: Option<PathBuf>,
    threads: Option<usize>,
) -> PyResult<Py<PyAny>> {
    guarded(|| {
        let src = grains_sim::Source::read(&path).map_err(InputError::new_err)?;
        let out = match out {
            Some(o) => o,
            None => {
                let s = grains_sim::scenario::parse(&src).map_err(InputError::new_err)?;
                grains_sim::driver::default_out(s.name())
            }
        };
        let done = py.detach(|| {
            let go = || grains_sim::run::run(&src, grains_sim::RunOptions::new(out));
            match threads {
                Some(n) => rayon::ThreadPoolBuilder::new()
                    .num_threads(n)
                    .build()
                    .map_err(|e| grains_sim::RunError::Input(format!("threads = {n}: {e}")))?
                    .install(go),
                None => go(),
            }
        });
        let done = done.map_err(|e| match e {
            grains_sim::RunError::Input(m) => InputError::new_err(m),
            grains_sim::RunError::Output(e) => PyOSError::new_err(format!("{e:#}")),
        })?;
        let v = serde_json::to_value(&done.summary)
            .map_err(|e| InternalError::new_err(e.to_string()))?;
        from_json(py, &v)
    })
}

/// Makes the packing of the spec at `spec` as `grains pack` does, writing into `out`
/// (default `runs/pack_<stem>`); returns the summary's figures with the disks'
/// `position` (N, 2) and `radius` (N,) arrays and the output directory `out`.
#[pyfunction]
#[pyo3(signature = (spec, out=None))]
fn pack(py: Python<'_>, spec: PathBuf, out: Option<PathBuf>) -> PyResult<Py<PyAny>> {
    guarded(|| {
        let (s, text, v) = grains_sim::pack::prepare(&spec).map_err(InputError::new_err)?;
        let stem = spec
            .file_stem()
            .map(|s| s.to_string_lossy().to_string())
            .unwrap_or_else(|| "packing".into());
        let out = out.unwrap_or_else(|| grains_sim::driver::default_out(&format!("pack_{stem}")));
        let packed = py
            .detach(|| grains_sim::pack::pack(&s, &text, &v, &out, &mut |_line: String| {}))
            .map_err(|e| PyOSError::new_err(format!("{e:#}")))?;
        let d = from_json(py, &serde_json::Value::Object(packed.summary))?;
        let d = d.bind(py);
        let sample = grains_analysis::sample::load(&out.join("packing.txt"))
            .map_err(|e| PyOSError::new_err(e.to_string()))?;
        d.set_item("position", arrays::rows(py, &sample.pos))?;
        d.set_item("radius", arrays::scalars(py, sample.radius.clone()))?;
        d.set_item("out", out)?;
        Ok(d.clone().unbind())
    })
}

/// Analyses `path` as `grains analyze` does: a run directory (the dispersal analysis of
/// its frames) or a packing file or DEM frame (microstructure); writes into `out`
/// (default: `<run>/analysis`, or `runs/analyze_<stem>`) and returns the figures.
#[pyfunction]
#[pyo3(signature = (path, out=None))]
fn analyze(py: Python<'_>, path: PathBuf, out: Option<PathBuf>) -> PyResult<Py<PyAny>> {
    guarded(|| {
        use grains_sim::dispersal::run_dir;
        let figures = if run_dir::is_run_dir(&path) {
            let out = out.unwrap_or_else(|| path.join("analysis"));
            py.detach(|| run_dir::analyze_run(&path, &out, None))
        } else {
            let stem = path
                .file_stem()
                .map(|s| s.to_string_lossy().to_string())
                .unwrap_or_else(|| "sample".into());
            let out =
                out.unwrap_or_else(|| grains_sim::driver::default_out(&format!("analyze_{stem}")));
            py.detach(|| grains_sim::analyze::analyze(&path, &out))
        }
        .map_err(InputError::new_err)?;
        from_json(py, &serde_json::Value::Object(figures))
    })
}

/// For the test suite: panics with `message` inside a guarded call (with `pool`, on a
/// worker of the thread pool, the GIL released), to show a panic becomes InternalError.
#[pyfunction]
#[pyo3(signature = (message, pool=false))]
fn _panic(py: Python<'_>, message: String, pool: bool) -> PyResult<()> {
    guarded(|| {
        if pool {
            py.detach(|| rayon::scope(|s| s.spawn(|_| panic!("{message}"))));
        }
        panic!("{message}")
    })
}

/// grains: DEM (2D and 3D), MPM and FEM–DEM simulations of granular materials, from Python.
#[pymodule]
fn grains(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("InputError", py.get_type::<InputError>())?;
    m.add("InternalError", py.get_type::<InternalError>())?;
    m.add("StaleViewError", py.get_type::<StaleViewError>())?;
    m.add_class::<sim::Simulation>()?;
    m.add_class::<sim::Particles>()?;
    m.add_class::<view::View>()?;
    m.add_class::<view::Guard>()?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(pack, m)?)?;
    m.add_function(wrap_pyfunction!(analyze, m)?)?;
    m.add_function(wrap_pyfunction!(_panic, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
