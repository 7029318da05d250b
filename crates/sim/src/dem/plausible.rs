//! What is legal but physically implausible: warned about before a run (`grains check`
//! and `grains run` print the same lines), and what a running state must never do (leave
//! its domain, move further than its radius in one step), which stops the run as
//! unstable rather than letting it report a result.

use super::assemble::Assembled;
use super::scenario::Scenario;
use grains_core::input::shown;
use grains_dem::{Setup, State};

/// A Coulomb friction coefficient above this is no granular material's (sand and glass
/// are 0.2–0.8; rubber on rough rock reaches about 1.5).
const MAX_PLAUSIBLE_FRICTION: f64 = 2.0;
/// A speed above this is beyond a detonation's (TNT: 6.9 km/s).
const MAX_PLAUSIBLE_SPEED: f64 = 1.0e4;
/// A gravity above this many g is no planet's nor a centrifuge's.
const MAX_PLAUSIBLE_G: f64 = 1.0e5;
/// A particle may move at most this fraction of its radius per step before contacts
/// are resolved poorly (the step limit is set by stiffness alone, not by speed).
const MAX_STEP_TRAVEL: f64 = 0.1;

/// The warnings for a scenario `s` as assembled in `a`, each naming its key and figure.
pub fn warnings(s: &Scenario, a: &Assembled) -> Vec<String> {
    let mut out = Vec::new();
    for m in &s.materials {
        if let Some(mu) = m.friction.filter(|mu| *mu > MAX_PLAUSIBLE_FRICTION) {
            out.push(format!(
                "material.{}.friction = {}: implausibly high (granular materials have 0.2–0.8; above {MAX_PLAUSIBLE_FRICTION} is no real material)",
                m.name,
                shown(mu)
            ));
        }
    }
    let g = glam::DVec2::from(s.gravity).length();
    if g > MAX_PLAUSIBLE_G * 9.81 {
        out.push(format!(
            "gravity = {} m/s²: {:.2e} g, implausible (particles may pass through walls and leave the domain, which stops the run)",
            shown(g),
            g / 9.81
        ));
    }
    let p = &a.particles;
    let fastest = (0..p.len()).max_by(|&i, &j| p.vel[i].length().total_cmp(&p.vel[j].length()));
    if let Some(i) = fastest {
        let v = p.vel[i].length();
        let size = (a.setup.domain.hi - a.setup.domain.lo).max_element();
        if v > MAX_PLAUSIBLE_SPEED {
            out.push(format!(
                "particle {} starts at {} m/s: faster than a detonation (about 7e3 m/s); it crosses the {} m domain in {} s",
                p.id[i],
                shown(v),
                shown(size),
                shown(size / v)
            ));
        }
        let travel = v * a.dt / p.radius[i];
        if travel > MAX_STEP_TRAVEL {
            out.push(format!(
                "particle {} starts at {} m/s and moves {:.3} of its radius per step (dt = {} s): contacts are poorly resolved above {MAX_STEP_TRAVEL}; lower run.dt",
                p.id[i],
                shown(v),
                travel,
                shown(a.dt)
            ));
        }
    }
    out
}

/// Why the state cannot be trusted, if it cannot: a particle outside a non-periodic side
/// of the domain (it passed through a wall, or there was none) or moving more than its
/// radius in one step (it can pass through walls and disks unseen).
pub fn escaped(setup: &Setup, state: &State, dt: f64) -> Option<String> {
    let p = &state.particles;
    let d = &setup.domain;
    for i in 0..p.len() {
        let x = p.pos[i];
        let outside = (0..2).any(|a| !d.periodic[a] && (x[a] < d.lo[a] || x[a] > d.hi[a]));
        if outside {
            return Some(format!(
                "particle {} at ({}, {}) m left the domain [{}, {}] × [{}, {}] m (it passed through a wall, or there was none)",
                p.id[i],
                shown(x.x),
                shown(x.y),
                shown(d.lo.x),
                shown(d.hi.x),
                shown(d.lo.y),
                shown(d.hi.y)
            ));
        }
        let travel = p.vel[i].length() * dt;
        if travel > p.radius[i] {
            return Some(format!(
                "particle {} moves {} m per step, more than its radius {} m: it can pass through walls and disks; lower run.dt or the load",
                p.id[i],
                shown(travel),
                shown(p.radius[i])
            ));
        }
    }
    None
}
