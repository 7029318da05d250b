//! grains as a library: a scenario in, a running simulation, its outputs out.
//!
//! * [`source`] and [`scenario`]: a scenario file of any engine (DEM, MPM, FEM–DEM),
//!   parsed strictly; [`check`] derives what a run would cost without running it.
//! * [`driver`]: the one run loop every engine uses — a [`driver::Simulation`] steps,
//!   [`driver::Observer`]s watch (history, frames, probes, stop rules), a
//!   [`driver::Plan`] schedules samples, frames and checkpoints.
//! * [`dem`], [`mpm`], [`blast`]: each engine's scenario, assembly, simulation and
//!   observers; [`run`] runs any scenario the way `grains run` does.
//! * [`dispersal`]: the dispersal analysis of a ring (xue-2019 §§4.2–5) during a run
//!   and on a finished run's frames.
//! * [`pack`], [`analyze`], [`bench`]: the packing generator's, the microstructure
//!   analysis's and the benchmarks' front ends.
//!
//! A study can be scripted with these pieces: see `examples/ring.rs`, which runs the
//! FEM–DEM ring through the library and reads its particles every microsecond.

pub mod analyze;
pub mod bench;
pub mod blast;
pub mod check;
pub mod checkpoint;
pub mod collision;
pub mod dem;
pub mod dem3d;
pub mod dispersal;
pub mod driver;
pub mod estimate;
pub mod forces;
pub mod frames;
pub mod history;
pub mod law;
pub mod mpm;
pub mod output;
pub mod pack;
pub mod pack3d;
pub mod packings;
pub mod ranks;
pub mod run;
pub mod scenario;
pub mod session;
pub mod source;
pub mod summary;

pub use driver::{Clock, Observer, ParticleView, Simulation, Status};
pub use run::{Finished, RunError, RunOptions};
pub use source::Source;
