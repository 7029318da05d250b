//! The stable time step: a dilatational wave (plus the fastest material) may cross at
//! most one cell per step.

use crate::particles::Particles;
use crate::setup::{Motion, Setup};

/// The fastest plane-strain dilatational wave speed among the free bodies' materials.
pub fn wave_speed(setup: &Setup) -> f64 {
    setup
        .bodies
        .iter()
        .filter(|b| b.motion == Motion::Free)
        .map(|b| setup.materials[b.material].wave_speed())
        .fold(0.0, f64::max)
}

/// Largest stable step h / (c_max + |v|_max), with c the plane-strain dilatational wave
/// speed √((K + 4G/3)/ρ) of the stiffest free body's material and v the fastest point
/// or prescribed body.
pub fn critical_dt(setup: &Setup, p: &Particles) -> f64 {
    let c = wave_speed(setup);
    let v_points = p.vel.iter().map(|v| v.length()).fold(0.0, f64::max);
    let v_rigid = setup
        .bodies
        .iter()
        .filter_map(|b| match b.motion {
            Motion::Prescribed(v) => Some(v.length()),
            Motion::Free => None,
        })
        .fold(0.0, f64::max);
    setup.grid.h / (c + v_points.max(v_rigid))
}
