//! What the ledger's closure tests share (`granular_ledger.rs`, `wall_ledger.rs`): the
//! material, vectors and spins written once for both dimensions, and the test of a
//! residual first order in Δt.

#[cfg(feature = "dim3")]
use grains_dem3d as dem;

#[cfg(not(feature = "dim3"))]
use grains_dem as dem;

use dem::math::{AngVector, Components, Vector, DIM};
use dem::{ContactModel, EnergyLedger, Material, State};

/// Density of the grains (kg/m³).
pub const RHO: f64 = 2500.0;

/// A material of the granular law (its figures are in the law).
pub fn material() -> Material {
    Material {
        name: "m".into(),
        density: RHO,
        youngs: None,
        poisson: None,
        restitution: None,
        friction: None,
        inertia_factor: 0.4,
    }
}

/// The linear law a set-up is made with before its granular table replaces it.
pub fn placeholder() -> ContactModel {
    ContactModel::unused()
}

/// A vector from its horizontal components (the first DIM − 1 of `h`) and its vertical
/// one (the last axis).
pub fn at(h: [f64; 2], up: f64) -> Vector {
    let mut v = Vector::ZERO;
    for a in 0..DIM - 1 {
        v[a] = h[a];
    }
    v[DIM - 1] = up;
    v
}

/// An angular velocity about the second horizontal axis in 3D (rolling along the first)
/// and about the normal `twist`; in 2D the scalar spin `roll` (sign as in 3D: rolling
/// along +x without slip on a floor takes roll = v/r in 3D, −v/r in 2D).
pub fn spin(roll: f64, twist: f64) -> AngVector {
    if DIM == 3 {
        <AngVector as Components>::from_slice(&[0.0, roll, twist])
    } else {
        <AngVector as Components>::from_slice(&[-roll])
    }
}

/// Uniform numbers in [−½, ½) from a fixed seed (a linear congruential generator: the
/// same beds in every build).
pub fn noise() -> impl FnMut() -> f64 {
    let mut k = 7u64;
    move || {
        k = k
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (k >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}

/// What a closure run measured.
#[derive(Debug)]
pub struct Closure {
    /// |E_end + booked − work in − E_0| over the reference energy.
    pub residual: f64,
    /// E_0: the initial energy (kinetic + potential + stored).
    pub start: f64,
    /// The ledger at the end.
    pub ledger: EnergyLedger,
    /// The state at the end.
    pub state: State,
}

/// The closure at `dt` and `dt/2` against a bound first order in Δt (the ledger's
/// terms are exact per step; the dashpots and the slip are read at the half step while
/// the force acts over the whole: docs/architecture.md, *The energy ledger*): below
/// `bound` at Δt and below half of it at Δt/2.
pub fn converges(what: &str, run: impl Fn(f64) -> Closure, dt: f64, bound: f64) -> Closure {
    let coarse = run(dt);
    let fine = run(0.5 * dt);
    eprintln!(
        "{what} ({}D): residual {:.3e} at dt {dt:e}, {:.3e} at dt/2 (ratio {:.3}); ledger {:?}",
        DIM,
        coarse.residual,
        fine.residual,
        fine.residual / coarse.residual,
        fine.ledger
    );
    assert!(
        coarse.residual < bound && fine.residual < 0.5 * bound,
        "{what}: residuals {} at dt and {} at dt/2 against {bound} and its half",
        coarse.residual,
        fine.residual
    );
    fine
}
