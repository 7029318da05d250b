//! Velocity-Verlet integration of the nodes (the explicit update of Eq. A3, split into
//! two half kicks so that it shares its time levels with the DEM it may be coupled to),
//! with the global non-viscous damping of Eq. A5.

use crate::setup::FemSetup;
use crate::state::Charge;
use glam::DVec2;
use rayon::prelude::*;

const CHUNK: usize = 4096;

/// First half of the step: v += ½Δt·F/m with the last total force, then x += Δt·v.
/// Books the work of the external and damping forces over this half.
pub fn kick_drift(c: &mut Charge, dt: f64) {
    let n = &mut c.nodes;
    let h = 0.5 * dt;
    let (f_int, f_ext, f_damp, mass) = (&n.f_int, &n.f_ext, &n.f_damp, &n.mass);
    let works: Vec<(f64, f64)> = n
        .pos
        .par_chunks_mut(CHUNK)
        .zip(n.pos_prev.par_chunks_mut(CHUNK))
        .zip(n.vel.par_chunks_mut(CHUNK))
        .enumerate()
        .map(|(ci, ((x, x_prev), v))| {
            let (mut we, mut wd) = (0.0, 0.0);
            for k in 0..x.len() {
                let i = ci * CHUNK + k;
                let f = f_int[i] + f_ext[i] + f_damp[i];
                v[k] += h * f / mass[i];
                we += h * f_ext[i].dot(v[k]);
                wd += h * f_damp[i].dot(v[k]);
                x_prev[k] = x[k];
                x[k] += dt * v[k];
            }
            (we, wd)
        })
        .collect();
    for (we, wd) in works {
        c.work_external += we;
        c.work_damping += wd;
    }
}

/// Second half of the step, after the internal (and any external) forces at x^(n+1)
/// are in: damping F_d = −α|F_int + F_ext|·v/|v| (Eq. A5, v the mid-step velocity),
/// then v += ½Δt·F/m. Advances the clock.
pub fn kick(setup: &FemSetup, c: &mut Charge, dt: f64) {
    let n = &mut c.nodes;
    let h = 0.5 * dt;
    let alpha = setup.damping;
    let (f_int, f_ext, mass) = (&n.f_int, &n.f_ext, &n.mass);
    let works: Vec<(f64, f64)> = n
        .vel
        .par_chunks_mut(CHUNK)
        .zip(n.f_damp.par_chunks_mut(CHUNK))
        .enumerate()
        .map(|(ci, (v, fd))| {
            let (mut we, mut wd) = (0.0, 0.0);
            for k in 0..v.len() {
                let i = ci * CHUNK + k;
                let speed = v[k].length();
                fd[k] = if alpha > 0.0 && speed > 0.0 {
                    -alpha * (f_int[i] + f_ext[i]).length() * v[k] / speed
                } else {
                    DVec2::ZERO
                };
                we += h * f_ext[i].dot(v[k]);
                wd += h * fd[k].dot(v[k]);
                v[k] += h * (f_int[i] + f_ext[i] + fd[k]) / mass[i];
            }
            (we, wd)
        })
        .collect();
    for (we, wd) in works {
        c.work_external += we;
        c.work_damping += wd;
    }
    c.time += dt;
    c.step += 1;
}
