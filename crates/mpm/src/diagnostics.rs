//! What a run records: energies (with the energy dissipated by plasticity and viscosity
//! and the work of thermal strains), momentum, and per body the centre of mass, velocity,
//! angular velocity, rotation angle, plastic strain and debonded length. Sums run over
//! fixed chunks in a fixed order, so they do not depend on the thread count.

use crate::bond;
use crate::particles::Particles;
use crate::setup::{Motion, Setup};
use crate::CHUNK;
use glam::DVec2;
use rayon::prelude::*;

/// Kinematics of one body.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyDiag {
    /// Mass.
    pub mass: f64,
    /// Centre of mass.
    pub centre: DVec2,
    /// Centre-of-mass velocity.
    pub velocity: DVec2,
    /// Angular velocity about the centre of mass, L/I (rad/s, counter-clockwise > 0).
    pub omega: f64,
    /// Best-fit rotation from the initial configuration, in (−π, π] (rad); unwrap
    /// between samples to accumulate turns.
    pub angle: f64,
    /// Kinetic energy.
    pub kinetic: f64,
    /// Stored (strain) energy.
    pub strain: f64,
    /// Energy dissipated by plastic work and viscosity.
    pub dissipated: f64,
    /// Work done by thermal strains.
    pub thermal_work: f64,
    /// Largest equivalent plastic strain.
    pub plastic_max: f64,
    /// Surface and debonded lengths (zeros for a body without a bond).
    pub lengths: bond::Lengths,
}

/// Whole-system figures.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Diagnostics {
    /// Kinetic energy Σ ½ m v² of the free bodies (J per unit thickness).
    pub kinetic: f64,
    /// Stored elastic energy.
    pub strain: f64,
    /// Energy dissipated so far by plastic work and viscosity (free bodies).
    pub dissipated: f64,
    /// Work done so far on the free bodies by their thermal strains.
    pub thermal_work: f64,
    /// Gravitational potential energy −Σ m g·x of the free bodies.
    pub potential: f64,
    /// Total momentum of the free bodies.
    pub momentum: DVec2,
    /// Largest point speed.
    pub max_speed: f64,
    /// Every position, velocity and stress is finite.
    pub finite: bool,
    /// Per body.
    pub bodies: Vec<BodyDiag>,
}

impl Diagnostics {
    /// Kinetic + strain + potential.
    pub fn total(&self) -> f64 {
        self.kinetic + self.strain + self.potential
    }

    /// Total + dissipated − thermal work: constant up to the discretisation's own error
    /// when only prescribed temperatures and gravity act (no rigid movers, no walls'
    /// friction).
    pub fn balance(&self) -> f64 {
        self.total() + self.dissipated - self.thermal_work
    }
}

#[derive(Clone, Copy, Default)]
struct Sums {
    m: f64,
    mx: DVec2,
    mv: DVec2,
    m0: DVec2,
    ke: f64,
    se: f64,
    pe: f64,
    de: f64,
    tw: f64,
    epmax: f64,
    vmax: f64,
    bad: bool,
}

#[derive(Clone, Copy, Default)]
struct Moments {
    l: f64,
    i: f64,
    cross: f64,
    dot: f64,
}

/// Measures the state. `ranges[b]` is body b's point range (see [`crate::Solver::layout`]).
pub fn measure(setup: &Setup, p: &Particles, ranges: &[(usize, usize)]) -> Diagnostics {
    let g = setup.gravity;
    let mut d = Diagnostics {
        finite: true,
        ..Default::default()
    };
    let period = setup.grid.period_y();
    for (b, body) in setup.bodies.iter().enumerate() {
        let (start, end) = ranges[b];
        let mat = &setup.materials[body.material];
        let free = body.motion == Motion::Free;
        // Along a periodic y a body's points are seen from one of them (minimum image),
        // so a body across the seam has its centre and moments in one piece.
        let seen_from = |x: DVec2, r: DVec2| match period {
            None => x,
            Some(l) => {
                let d = x.y - r.y;
                DVec2::new(x.x, r.y + d - l * (d / l).round())
            }
        };
        let (r, r0) = if start < end {
            (p.pos[start], p.pos0[start])
        } else {
            (DVec2::ZERO, DVec2::ZERO)
        };
        let chunks: Vec<Sums> = (start..end)
            .step_by(CHUNK)
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|c0| {
                let mut s = Sums::default();
                for i in c0..(c0 + CHUNK).min(end) {
                    let (m, x, v) = (p.mass[i], seen_from(p.pos[i], r), p.vel[i]);
                    s.m += m;
                    s.mx += m * x;
                    s.mv += m * v;
                    s.m0 += m * seen_from(p.pos0[i], r0);
                    s.ke += 0.5 * m * v.length_squared();
                    s.pe -= m * g.dot(x);
                    if free {
                        s.se +=
                            mat.stored_energy(p.vol0[i], p.def[i], &p.stress[i], p.branches_of(i));
                        s.de += p.dissipated[i];
                        s.tw += p.thermal_work[i];
                        s.epmax = s.epmax.max(p.plastic[i]);
                    }
                    s.vmax = s.vmax.max(v.length());
                    let st = p.stress[i];
                    s.bad |= !(x.is_finite()
                        && v.is_finite()
                        && (st.xx + st.yy + st.xy + st.zz).is_finite());
                }
                s
            })
            .collect();
        let mut s = Sums::default();
        for c in chunks {
            s.m += c.m;
            s.mx += c.mx;
            s.mv += c.mv;
            s.m0 += c.m0;
            s.ke += c.ke;
            s.se += c.se;
            s.pe += c.pe;
            s.de += c.de;
            s.tw += c.tw;
            s.epmax = s.epmax.max(c.epmax);
            s.vmax = s.vmax.max(c.vmax);
            s.bad |= c.bad;
        }
        let (centre, vel, centre0) = (s.mx / s.m, s.mv / s.m, s.m0 / s.m);
        let moments: Vec<Moments> = (start..end)
            .step_by(CHUNK)
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|c0| {
                let mut q = Moments::default();
                for i in c0..(c0 + CHUNK).min(end) {
                    let m = p.mass[i];
                    let r = seen_from(p.pos[i], r) - centre;
                    let r0 = seen_from(p.pos0[i], r0) - centre0;
                    q.l += m * r.perp_dot(p.vel[i] - vel);
                    q.i += m * r.length_squared();
                    q.cross += m * r0.perp_dot(r);
                    q.dot += m * r0.dot(r);
                }
                q
            })
            .collect();
        let q = moments.iter().fold(Moments::default(), |a, c| Moments {
            l: a.l + c.l,
            i: a.i + c.i,
            cross: a.cross + c.cross,
            dot: a.dot + c.dot,
        });
        d.bodies.push(BodyDiag {
            mass: s.m,
            centre: setup.grid.wrap(centre),
            velocity: vel,
            omega: if q.i > 0.0 { q.l / q.i } else { 0.0 },
            angle: q.cross.atan2(q.dot),
            kinetic: s.ke,
            strain: s.se,
            dissipated: s.de,
            thermal_work: s.tw,
            plastic_max: s.epmax,
            lengths: bond::Lengths::default(),
        });
        d.finite &= !s.bad;
        d.max_speed = d.max_speed.max(s.vmax);
        if free {
            d.kinetic += s.ke;
            d.strain += s.se;
            d.dissipated += s.de;
            d.thermal_work += s.tw;
            d.potential += s.pe;
            d.momentum += s.mv;
        }
    }
    if setup.bonds() {
        for (b, l) in bond::lengths(setup, p, ranges).into_iter().enumerate() {
            d.bodies[b].lengths = l;
        }
    }
    d
}

/// A fingerprint of the points: FNV-1a over every point's position, velocity,
/// deformation gradient and stress, in id order. Equal hashes mean bitwise-equal runs,
/// whatever the thread count.
pub fn state_hash(p: &Particles) -> u64 {
    let mut h = grains_core::hash::Fnv1a::default();
    let mut order: Vec<usize> = (0..p.len()).collect();
    order.sort_unstable_by_key(|&i| p.id[i]);
    for i in order {
        let (x, v, f, s) = (p.pos[i], p.vel[i], p.def[i], p.stress[i]);
        for w in [
            x.x, x.y, v.x, v.y, f.x_axis.x, f.x_axis.y, f.y_axis.x, f.y_axis.y,
        ] {
            h.f64(w);
        }
        for w in [s.xx, s.yy, s.xy, s.zz] {
            h.f64(w);
        }
    }
    h.finish()
}
