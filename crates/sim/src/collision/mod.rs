//! Collision checks, from one source for both dimensions (as `crate::law`): a watch of a
//! particle's first impact on its partner (a particle or a wall) every step, timing
//! contact by the zero crossings of the gap interpolated within the step, and at the end
//! the measure set against Hertz's undamped impact, the pair's restitution or the
//! rigid-body sliding limit. `watch.rs` is compiled on `grains-dem` ([`dim2`]) and on
//! `grains-dem3d` ([`dim3`]).
//!
//! Hertz (E* and R* of the pair, R* = R and m* = m on a wall, v the approach speed):
//! δ_max = (15 m* v² / (16 E* √R*))^{2/5}, F_max = (4/3) E* √R* δ_max^{3/2},
//! t_c = 2 · (2/5) B(2/5, 1/2) δ_max / v = 2.94328 δ_max / v (= 2.868 (m*² / (R* E*² v))^{1/5}).
//! The normal motion is one-dimensional, so a disk obeys the same formulas with its own
//! mass (grains' disks: ρπR² per metre of thickness) and the law's sphere-contact force.
//! Sliding throughout an impact on a wall: v_t' = v_t − μ(1 + e) v_n and
//! ω' R = μ (1 + e) v_n / K, K = I / m R² (2/5 for a sphere, 1/2 for a disk; e measured);
//! it slides throughout while v_t / v_n ≥ μ (1 + e)(1 + 1/K) (3.5 μ(1 + e) for a sphere,
//! 3 μ(1 + e) for a disk).

use serde::{Deserialize, Serialize};

pub mod dim2;
pub mod dim3;

/// t_c v / δ_max of an undamped Hertz impact: 2 ∫₀¹ (1 − x^{5/2})^{−1/2} dx.
pub const HERTZ_TIME: f64 = 2.943_275_184_324_705;

/// What a collision check measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Measure {
    /// Largest overlap, against Hertz's δ_max.
    MaxOverlap,
    /// Largest contact force, against Hertz's F_max.
    PeakForce,
    /// Time in contact, against Hertz's t_c.
    ContactTime,
    /// −v_n(after)/v_n(before), against the pair's e.
    Restitution,
    /// Tangential speed after, against the rigid-body sliding limit v_t − μ(1 + e)v_n.
    TangentialVelocity,
    /// Spin ωR after, against the rigid-body sliding limit μ(1 + e)v_n / K.
    AngularVelocity,
}
