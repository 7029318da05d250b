//! Dense 2D disk packings with controlled microstructure (xue-2019 §3.1).
//!
//! The protocol ([`protocol`]), one stage per module:
//!
//! 1. [`lining`]: every wall is lined with a chain of small disks (≈ 0.6 d0) tangent
//!    to it, as in the paper.
//! 2. [`lattice`] (default) or [`deposit`]: the bulk disks, drawn from the size
//!    distribution ([`sizes`]), start on one triangular lattice (a single crystal
//!    orientation) or as a gravity-deposited bed.
//! 3. [`mc`]: hard-disk Monte Carlo with size swaps grows them at the protocol's `rate`
//!    per sweep from `start_fraction` until jammed.
//! 4. [`relax`]: the radii are swollen in small steps, each followed by a FIRE
//!    minimisation of harmonic overlaps, to close the last gaps.
//!
//! The same protocol and parameters serve every size distribution: from the lattice, a
//! narrow one (Gaussian δ = 0.113) keeps the crystal and its orientation, a broad one
//! (uniform δ = 0.177) rearranges and loses them. Results are reproducible for any
//! thread count: the start is sequential and seeded, the Monte Carlo uses per-cell
//! random streams, minimisation sums in fixed chunks.
#![warn(missing_docs)]

pub mod deposit;
pub mod lattice;
pub mod lining;
pub mod mc;
pub mod output;
pub mod preview;
pub mod protocol;
pub mod relax;
pub mod ring;
pub mod sizes;
pub mod sort;
pub mod spec;
pub mod sphere_spec;
pub mod spheres;
pub mod validate;

pub use protocol::{pack, Packing, ProtocolStats, Watch};
pub use spec::{parse, PackSpec};
pub use validate::{validate, Validated};
