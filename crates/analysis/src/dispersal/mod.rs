//! Analysis of a dispersing particle ring as in xue-2019 §§4.2–5: coarse-grained polar
//! fields, fronts, profiles, compact band and spall, spiral shear bands and jets.
//!
//! Everything works on plain slices ([`ParticleSet`], [`Contacts`]) so any engine or a
//! frame read from disk can feed it; nothing here depends on an engine crate.
//!
//! * [`polar`]: the grid of bins (dr = 5 d0, dθ = π/90 about the charge centre).
//! * [`fields`]: [`coarse_grain`] → [`PolarFields`] — packing fraction, velocity,
//!   ∇v, dilation rate, shear rate ([`gradient`]), stress and pressure ([`stress`]),
//!   with plain bins or a smoothing kernel ([`kernel`]).
//! * [`bands`]: compact band and spall ([`band_split`]).
//! * [`fronts`]: R_in, R_out, R_p, R_comp per frame and the PSF/RW/SSF phases over
//!   time ([`front_history`]).
//! * [`profiles`], [`spectra`]: radial and azimuthal profiles, Fourier spectra.
//! * [`shear_bands`]: clockwise and anticlockwise spiral bands at the inner perimeter.
//! * [`jets`]: spikes of the outer envelope, traced back by grain id.
//! * [`frame`]: [`analyze_frame`] runs all per-frame measures; [`DispersalSpec`] holds
//!   the settings.
//! * [`output`]: `.vts` grids, polar maps, R–t diagram, profile plots.
//! * [`synthetic`]: lattice rings with known fields, for tests and benchmarks.
#![allow(clippy::needless_range_loop)]

pub mod bands;
pub mod fields;
pub mod frame;
pub mod fronts;
pub mod gradient;
pub mod input;
pub mod jets;
pub mod kernel;
pub mod output;
pub mod polar;
pub mod profiles;
pub mod shear_bands;
pub mod spectra;
pub mod stress;
pub mod synthetic;

pub use bands::{band_split, BandMap, BandSpec, BandSplit, Layer, LayerFigures, LayerVelocity};
pub use fields::{coarse_grain, PolarFields};
pub use frame::{analyze_frame, DispersalSpec, FrameAnalysis, FrameSummary, ShearBandSummary};
pub use fronts::{frame_fronts, front_history, FrameFronts, FrontHistory, FrontPhase, FrontSpec};
pub use input::{Contacts, InputError, ParticleSet, StressSource};
pub use jets::{jets, trace_jets, Jet, JetOrigin, JetSpec, Jets};
pub use kernel::Kernel;
pub use output::{
    fields_grid, plot_azimuthal, plot_fronts, plot_radial_profiles, write_maps, MapOverlays,
};
pub use polar::{Binning, PolarGrid};
pub use profiles::{azimuthal_profile, radial_profile, AzimuthalProfile, RadialProfile};
pub use shear_bands::{shear_bands, ShearBandSpec, ShearBands, SpiralFamily};
pub use spectra::{spectrum, Spectrum};
pub use stress::StressField;
