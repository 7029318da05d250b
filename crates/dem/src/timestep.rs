//! The stable time step of the explicit integrator, as the contact law bounds it
//! ([`ContactLaw::stable_step`]).
//!
//! Velocity Verlet integrates an oscillator of frequency ω stably for ω·Δt < 2, and a
//! viscously damped one for ω·Δt < 2(√(1+ζ²) − ζ). The stiffest contacts are those of
//! the lightest (and smallest) particles: each material's lightest particle is paired
//! with every material's and with each wall of its own material. The largest ω and the
//! largest ζ over those pairs are combined (each bounds its own pair; together they
//! bound every pair), and a law that bounds the step by a time instead
//! ([`StepBound::Time`], Hertz's Rayleigh time) caps the result.

use crate::contact::PairTable;
use crate::law::{Body, ContactLaw, StepBound};
use crate::particles::Particles;
use crate::setup::Setup;

/// The largest stable time step for these particles under the set-up's contact law (s),
/// or infinity when there are no particles.
pub fn critical_dt(setup: &Setup, particles: &Particles) -> f64 {
    match &setup.granular {
        Some(table) => bound(setup, table, particles),
        None => bound(setup, &setup.pairs, particles),
    }
}

fn bound<L: ContactLaw>(setup: &Setup, table: &PairTable<L>, particles: &Particles) -> f64 {
    let mut omega_max: f64 = 0.0;
    let mut zeta_max: f64 = 0.0;
    let mut time = f64::INFINITY;
    let mut take = |b: StepBound| match b {
        StepBound::Oscillator { omega, zeta } => {
            omega_max = omega_max.max(omega);
            zeta_max = zeta_max.max(zeta);
        }
        StepBound::Time(t) => time = time.min(t),
    };
    // The lightest and the smallest particle of each material bound its pairs.
    let nmat = setup.materials.len();
    let mut lightest = vec![f64::INFINITY; nmat];
    let mut smallest = vec![f64::INFINITY; nmat];
    for i in 0..particles.len() {
        let k = particles.material[i] as usize;
        lightest[k] = lightest[k].min(particles.mass(i));
        smallest[k] = smallest[k].min(particles.radius[i]);
    }
    let bodies: Vec<Option<Body>> = (0..nmat)
        .map(|a| {
            lightest[a].is_finite().then(|| Body {
                mass: lightest[a],
                radius: smallest[a],
                material: &setup.materials[a],
            })
        })
        .collect();
    for (a, ba) in bodies.iter().enumerate() {
        let Some(ba) = ba else { continue };
        for (b, bb) in bodies.iter().enumerate() {
            if let Some(bb) = bb {
                take(table.get(a, b).stable_step(ba, Some(bb)));
            }
        }
    }
    // A wall of another material is an infinitely heavy partner.
    for wall in &setup.walls {
        let Some(wm) = wall.material else { continue };
        for (a, ba) in bodies.iter().enumerate() {
            if let Some(ba) = ba {
                take(table.get(a, wm as usize).stable_step(ba, None));
            }
        }
    }
    if omega_max == 0.0 {
        return time;
    }
    time.min(2.0 / omega_max * ((1.0 + zeta_max * zeta_max).sqrt() - zeta_max))
}
