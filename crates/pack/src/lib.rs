//! Dense 2D disk packings with controlled microstructure (xue-2019 §3.1).
//!
//! The protocol, one stage per module:
//!
//! 1. [`lining`]: every wall is lined with a chain of small disks (≈ 0.6 d0) tangent
//!    to it, as in the paper.
//! 2. [`deposit`]: bulk disks, drawn from the size distribution ([`sizes`]), are poured
//!    in under gravity one at a time; the `rate` parameter says how far above the
//!    lowest free pocket a disk may stop (0 = slowest = most ordered).
//! 3. [`relax`]: the bed is swollen in small steps, each followed by a FIRE minimisation
//!    of harmonic overlaps, until the bulk reaches the target packing fraction.
//!
//! The same protocol and parameters serve every size distribution: a narrow one
//! (Gaussian δ = 0.113) crystallises in rows set by gravity, a broad one (uniform
//! δ = 0.177) cannot and stays amorphous. Results are reproducible for any thread
//! count: deposition is sequential and seeded, minimisation sums in fixed chunks.
#![warn(missing_docs)]

pub mod deposit;
pub mod lattice;
pub mod lining;
pub mod mc;
pub mod output;
pub mod protocol;
pub mod relax;
pub mod sizes;
pub mod spec;
pub mod validate;

pub use protocol::{pack, Packing, ProtocolStats};
pub use spec::{parse, PackSpec};
pub use validate::{validate, SpecError, Validated};
