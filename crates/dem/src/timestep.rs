//! The stable time step of the explicit integrator.
//!
//! Velocity Verlet integrates an oscillator of frequency ω stably for ω·Δt < 2, and a
//! viscously damped one for ω·Δt < 2(√(1+ζ²) − ζ). The stiffest modes are the normal
//! mode of two of the lightest particles (ω² = kn/m_eff, m_eff = m/2) and the tangential
//! mode of their contact points, whose effective inverse mass also carries rotation:
//! 1/m + r²/I per disk, i.e. (1 + 1/f)/m with I = f m r².

use crate::particles::Particles;
use crate::setup::Setup;

/// The largest stable time step for these particles and this contact table (s), or
/// infinity when there are no particles.
pub fn critical_dt(setup: &Setup, particles: &Particles) -> f64 {
    let mut omega_max: f64 = 0.0;
    let mut zeta_max: f64 = 0.0;
    // The lightest particle of each material bounds that material's pairs.
    let nmat = setup.materials.len();
    let mut lightest = vec![f64::INFINITY; nmat];
    for i in 0..particles.len() {
        let m = particles.mass(i);
        let k = particles.material[i] as usize;
        lightest[k] = lightest[k].min(m);
    }
    for a in 0..nmat {
        for b in 0..nmat {
            if !lightest[a].is_finite() || !lightest[b].is_finite() {
                continue;
            }
            let p = setup.pairs.get(a, b);
            let m_eff = 1.0 / (1.0 / lightest[a] + 1.0 / lightest[b]);
            let fa = setup.materials[a].inertia_factor;
            let fb = setup.materials[b].inertia_factor;
            let inv_t = (1.0 + 1.0 / fa) / lightest[a] + (1.0 + 1.0 / fb) / lightest[b];
            let wn = (p.kn / m_eff).sqrt();
            let wt = (p.kt * inv_t).sqrt();
            let zeta = p.normal_dashpot(m_eff) / (2.0 * m_eff * wn);
            omega_max = omega_max.max(wn).max(wt);
            zeta_max = zeta_max.max(zeta);
        }
    }
    // A wall of another material is an infinitely heavy partner: m_eff = m.
    for wall in &setup.walls {
        let Some(wm) = wall.material else { continue };
        for (a, &m) in lightest.iter().enumerate() {
            if !m.is_finite() {
                continue;
            }
            let p = setup.pairs.get(a, wm as usize);
            let f = setup.materials[a].inertia_factor;
            let wn = (p.kn / m).sqrt();
            let wt = (p.kt * (1.0 + 1.0 / f) / m).sqrt();
            omega_max = omega_max.max(wn).max(wt);
            zeta_max = zeta_max.max(p.normal_dashpot(m) / (2.0 * m * wn));
        }
    }
    if omega_max == 0.0 {
        return f64::INFINITY;
    }
    2.0 / omega_max * ((1.0 + zeta_max * zeta_max).sqrt() - zeta_max)
}
