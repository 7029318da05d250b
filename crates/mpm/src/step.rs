//! One explicit MPM step, as a fixed sequence of named stages:
//!
//! `prepare → p2g → correct(interpolated) → [usf: stress_first] → integrate →
//!  correct(integrated) → grid_velocities → g2p → [musl: remap → correct → stress_last]
//!  → [bonds failed: forget_bonds]`
//!
//! State is the points ([`State`]); the [`Solver`] only holds scratch space (patches, the
//! global sums, the sort layout) that is rebuilt every step. Every stress pass prepares
//! each body's material once for its time window (step length, temperature change) and
//! runs a kernel compiled for that model.

use crate::contact::{self, Crowd, Others, Pass, Touch};
use crate::models::{with_model, ElasticStep, Prepared};
use crate::nodes::{Global, Kin, Patch};
use crate::particles::{Layout, Particles};
use crate::setup::{Motion, Setup, UpdateScheme};
use crate::shape::{Bspline2, Gimp, Kernel, Linear, ShapeFunction};
use crate::tasks::{source, split, split_cache, split_points, views};
use crate::thermal::Thermal;
use crate::transfer::{self, Place, Seen, Stencil};
use glam::DVec2;
use rayon::prelude::*;

/// Everything that evolves during a run.
#[derive(Clone, Debug, Default)]
pub struct State {
    /// The material points.
    pub particles: Particles,
    /// Simulated time (s).
    pub time: f64,
    /// Steps taken.
    pub step: u64,
    /// Per body: what its fields were corrected against in the last step.
    pub touch: Vec<Touch>,
}

impl State {
    /// A fresh state at t = 0 for `setup`: the points get their bodies' bond strengths
    /// and the storage their materials' internal state needs.
    pub fn new(setup: &Setup, mut particles: Particles) -> Self {
        setup.prepare_points(&mut particles);
        State {
            particles,
            ..Default::default()
        }
    }
}

/// Why a step could not be taken.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct Unstable(pub String);

/// Scratch space of the stages; rebuilt every step, kept to reuse its allocations.
#[derive(Clone, Debug, Default)]
pub struct Solver {
    layout: Layout,
    resort: bool,
    bounds: Vec<(DVec2, DVec2)>,
    rigid: Vec<bool>,
    /// Each body's grid patch (after a step: the fields of that step's grid).
    pub patches: Vec<Patch>,
    /// Sums over bodies (only with more than one body).
    pub global: Option<Global>,
    next: Vec<DVec2>,
    stencils: Vec<Stencil>,
    density: Vec<f64>,
    crowds: crate::crowd::Crowds,
}

impl Solver {
    /// Scratch for `setup`; sorts the points (and sizes their Maxwell branch storage if
    /// the state was not made by [`State::new`]).
    pub fn new(setup: &Setup, state: &mut State) -> Self {
        let nb = setup.bodies.len();
        state.particles.set_branch_width(setup.branch_width());
        let mut w = Solver {
            layout: state.particles.sort(&setup.grid, nb),
            resort: false,
            bounds: vec![(DVec2::INFINITY, DVec2::NEG_INFINITY); nb],
            rigid: setup
                .bodies
                .iter()
                .map(|b| matches!(b.motion, Motion::Prescribed(_)))
                .collect(),
            patches: vec![Patch::default(); nb],
            density: setup
                .bodies
                .iter()
                .map(|b| setup.materials[b.material].density())
                .collect(),
            global: setup
                .multi_body()
                .then(|| Global::new(&setup.grid, setup.bonds())),
            ..Default::default()
        };
        let p = &state.particles;
        for i in 0..p.len() {
            let b = &mut w.bounds[p.body[i] as usize];
            *b = (b.0.min(p.pos[i]), b.1.max(p.pos[i]));
        }
        state.touch = vec![Touch::default(); nb];
        w
    }

    /// Where each body's points sit in the sorted arrays.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }
}

/// Advances the state by one time step `dt`.
pub fn step(setup: &Setup, s: &mut State, w: &mut Solver, dt: f64) -> Result<(), Unstable> {
    match setup.shape {
        ShapeFunction::Linear => step_with::<Linear>(setup, s, w, dt),
        ShapeFunction::Gimp => step_with::<Gimp>(setup, s, w, dt),
        ShapeFunction::Bspline2 => step_with::<Bspline2>(setup, s, w, dt),
    }
}

fn step_with<K: Kernel>(
    setup: &Setup,
    s: &mut State,
    w: &mut Solver,
    dt: f64,
) -> Result<(), Unstable> {
    let t = s.time;
    prepare(setup, &mut s.particles, w);
    p2g::<K>(setup, &s.particles, w);
    let mut touch = correct(setup, w, Pass::Interpolated, false, dt);
    match setup.scheme {
        UpdateScheme::Usf => stress_first::<K>(setup, &mut s.particles, w, (t, dt)),
        UpdateScheme::Usavg => stress_first::<K>(setup, &mut s.particles, w, (t, 0.5 * dt)),
        _ => {}
    }
    integrate(setup, w, dt);
    touch = merge(touch, correct(setup, w, Pass::Integrated, true, dt));
    grid_velocities(setup, w, dt, Some(&mut touch));
    let seen = g2p::<K>(setup, &mut s.particles, w, (t, dt), &mut touch);
    if setup.scheme == UpdateScheme::Musl {
        remap::<K>(setup, &s.particles, w);
        touch = merge(touch, correct(setup, w, Pass::Interpolated, true, dt));
        grid_velocities(setup, w, dt, None);
        stress_last::<K>(setup, &mut s.particles, w, (t, dt));
    }
    if touch.iter().any(|t| t.debonded > 0) {
        unfold(setup, w);
        forget_bonds::<K>(&mut s.particles, w);
    }
    s.touch = touch;
    s.time += dt;
    s.step += 1;
    finish(setup, s, w, seen)
}

/// Each body's material prepared for a stress pass of length `len` from time `t0`.
fn prepared(setup: &Setup, (t0, len): (f64, f64)) -> Vec<Prepared> {
    setup
        .bodies
        .iter()
        .map(|b| {
            let th = Thermal::over(b.temperature.as_ref(), t0, t0 + len);
            setup.materials[b.material].prepare(len, th)
        })
        .collect()
}

fn merge(a: Vec<Touch>, b: Vec<Touch>) -> Vec<Touch> {
    a.into_iter().zip(b).map(|(x, y)| x.merge(y)).collect()
}

fn place(setup: &Setup) -> Place {
    Place {
        lo: setup.grid.lo,
        inv_h: 1.0 / setup.grid.h,
        lp: setup.half_width,
        wrap_y: setup.grid.period_y().map(|l| (setup.grid.lo.y, l)),
    }
}

/// Re-sorts the points if any left its strip, and sizes each body's patch to its points.
fn prepare(setup: &Setup, p: &mut Particles, w: &mut Solver) {
    if w.resort {
        w.layout = p.sort(&setup.grid, setup.bodies.len());
        w.resort = false;
    }
    let grid = &setup.grid;
    let stored = grid.stored();
    let keep = setup.separation.is_some() && setup.multi_body();
    let bonds = setup.bonds();
    w.patches
        .par_iter_mut()
        .zip(&w.bounds)
        .zip(&w.rigid)
        .for_each(|((patch, &(lo, hi)), &rigid)| {
            let (a, z) = (grid.cell_of(lo), grid.cell_of(hi));
            // Cells [a, z] reach stored nodes [a, z + 3] (3-node stencil, one ghost).
            let hi = [(z[0] + 4).min(stored[0]), (z[1] + 4).min(stored[1])];
            patch.reset(a, hi, keep, bonds, setup.ledger && !rigid);
        });
}

/// Mass, momentum, mass gradient (several bodies) and, for USL/MUSL, internal force.
fn p2g<K: Kernel>(setup: &Setup, p: &Particles, w: &mut Solver) {
    let place = place(setup);
    let src = source(p);
    let force = matches!(setup.scheme, UpdateScheme::Usl | UpdateScheme::Musl);
    let grad = setup.multi_body();
    let bonds = setup.bonds();
    let rigid = &w.rigid;
    w.stencils.resize(p.len(), Stencil::default());
    for colour in 0..2 {
        let layout = &w.layout;
        let mut caches = split_cache(&mut w.stencils, layout);
        views(&mut w.patches, layout, colour)
            .into_iter()
            .map(|(k, view)| (k, view, caches[k].take().expect("one piece per strip")))
            .collect::<Vec<_>>()
            .into_par_iter()
            .for_each(|(k, mut view, cache)| {
                let (b, _, start, end) = layout.strips[k];
                let r = (start, end);
                let v = &mut view;
                use transfer::scatter;
                match (force && !rigid[b as usize], grad, bonds) {
                    (true, true, true) => scatter::<K, true, true, true>(&place, src, r, v, cache),
                    (true, true, false) => {
                        scatter::<K, true, true, false>(&place, src, r, v, cache)
                    }
                    (false, true, true) => {
                        scatter::<K, false, true, true>(&place, src, r, v, cache)
                    }
                    (false, true, false) => {
                        scatter::<K, false, true, false>(&place, src, r, v, cache)
                    }
                    (true, false, _) => scatter::<K, true, false, false>(&place, src, r, v, cache),
                    (false, false, _) => {
                        scatter::<K, false, false, false>(&place, src, r, v, cache)
                    }
                }
            });
    }
    fold(setup, w);
}

/// Along a periodic y, each patch's image rows added to their canonical rows.
fn fold(setup: &Setup, w: &mut Solver) {
    if let Some(rows) = setup.grid.canonical_rows() {
        let h = setup.grid.h;
        w.patches.par_iter_mut().for_each(|p| p.fold(rows, h));
    }
}

/// Along a periodic y, the canonical rows' kinematics copied to the images.
fn unfold(setup: &Setup, w: &mut Solver) {
    if let Some(rows) = setup.grid.canonical_rows() {
        w.patches.par_iter_mut().for_each(|p| p.unfold(rows));
    }
}

/// One contact correction: sums the bodies (if several), then corrects each free body
/// against the others and the walls.
fn correct(setup: &Setup, w: &mut Solver, pass: Pass, momentum_only: bool, dt: f64) -> Vec<Touch> {
    if (setup.pass1_to_particles || setup.ledger) && pass == Pass::Interpolated && !momentum_only {
        // Keep the interpolated velocity so FLIP can see this pass's change too.
        w.patches.par_iter_mut().for_each(|patch| {
            for (n, k) in patch.nodes.iter().zip(patch.kin.iter_mut()) {
                k.a = if n.m > 0.0 { n.p / n.m } else { DVec2::ZERO };
            }
        });
    }
    if let Some(g) = &mut w.global {
        g.accumulate(&w.patches, &w.rigid, momentum_only);
        if pass == Pass::Integrated && !g.bond.is_empty() {
            // The forces the intact bonds carry, summed and smoothed along the interface
            // before any bond is tested.
            let others = others(setup, g, &w.density, false);
            w.patches
                .par_iter_mut()
                .enumerate()
                .filter(|(b, patch)| !w.rigid[*b] && !patch.bond.is_empty())
                .for_each(|(b, patch)| contact::bond_forces(b as u16, patch, &others, dt));
            g.accumulate_bonds(&w.patches, true);
            crate::bond::smooth(g);
        }
    }
    // The corrections that reach the particles count as impulses: the second pass, and
    // the first one's when it is passed on (not MUSL's re-mapped momenta).
    let counts = pass == Pass::Integrated || (setup.pass1_to_particles && !momentum_only);
    let global = w.global.as_ref();
    let (rigid, density) = (&w.rigid, &w.density);
    let crowd = match global {
        Some(g) if setup.crowd == Crowd::Pairwise => {
            let o = others(setup, g, density, counts);
            crate::crowd::resolve(&mut w.patches, &o, rigid, pass, dt, &mut w.crowds)
        }
        _ => vec![Touch::default(); w.patches.len()],
    };
    w.patches
        .par_iter_mut()
        .zip(crowd)
        .enumerate()
        .map(|(b, (patch, crowd))| {
            if rigid[b] {
                return crowd;
            }
            let t = match global {
                Some(g) => {
                    let o = others(setup, g, density, counts);
                    contact::bodies(b as u16, patch, &o, pass, dt)
                }
                None => Touch::default(),
            };
            crowd.merge(t).merge(contact::walls(
                patch,
                &setup.grid,
                &setup.walls,
                pass,
                counts,
                dt,
            ))
        })
        .collect()
}

/// What a body's contact correction reads besides its patch.
fn others<'a>(setup: &'a Setup, g: &'a Global, density: &'a [f64], counts: bool) -> Others<'a> {
    Others {
        global: &g.nodes,
        bond: &g.bond,
        rows: g.dims[1],
        wrap: g.wrap,
        h: setup.grid.h,
        table: &setup.contact,
        separation: setup.separation,
        density,
        pairwise: setup.crowd == Crowd::Pairwise,
        counts,
    }
}

/// USF (and USAVG's first half): strain rate from the corrected interpolated
/// velocities, stress over the time `window` (start, length), internal force.
fn stress_first<K: Kernel>(setup: &Setup, p: &mut Particles, w: &mut Solver, window: (f64, f64)) {
    let models = prepared(setup, window);
    w.patches.par_iter_mut().for_each(|patch| {
        for (n, k) in patch.nodes.iter().zip(patch.kin.iter_mut()) {
            k.v = if n.m > 0.0 { n.p / n.m } else { DVec2::ZERO };
        }
    });
    unfold(setup, w);
    for colour in 0..2 {
        let layout = &w.layout;
        let stencils = &w.stencils;
        let mut pts = split_points(p, layout, None);
        let mut views = views(&mut w.patches, layout, colour);
        let jobs: Vec<_> = views
            .iter_mut()
            .map(|(k, view)| (*k, view, pts[*k].take()))
            .collect();
        jobs.into_par_iter().for_each(|(k, view, pts)| {
            let (b, _, start, end) = layout.strips[k];
            let body = &setup.bodies[b as usize];
            if let (Motion::Free, Some(mut pts)) = (body.motion, pts) {
                let cache = &stencils[start..end];
                let mat = &mut pts.mat;
                with_model!(&models[b as usize], m => {
                    transfer::stress_and_force::<K, _>(m, mat, view, cache)
                });
            }
        });
    }
    fold(setup, w);
}

/// Gravity and integration of the free bodies' momenta: p* = p + (f + m g) Δt.
fn integrate(setup: &Setup, w: &mut Solver, dt: f64) {
    let g = setup.gravity;
    w.patches
        .par_iter_mut()
        .zip(&w.rigid)
        .for_each(|(patch, &rigid)| {
            if rigid {
                return;
            }
            for (k, n) in patch.nodes.iter_mut().enumerate() {
                if n.m > 0.0 {
                    n.f += n.m * g;
                    n.p += n.f * dt;
                    if let Some(l) = patch.ledger.get_mut(k) {
                        l.f = n.f;
                    }
                }
            }
        });
}

/// Nodal velocities and FLIP accelerations from the corrected momenta and forces.
/// With the ledger (`touch`), each free body's grid energy of the step ([`Touch::grid`]):
/// its kinetic energy change over the change the particles' update takes from the grid
/// (v₀ = v_f − a Δt → v_f), and the part of it its contact corrections did. The change
/// splits exactly at the midpoint v̄ = (v₀ + v_f)/2 into Σ m v̄·δv (corrections) and
/// Σ f·v̄ Δt (forces); the forces' work the stress update stores is Σ f·v_s Δt, with v_s
/// the velocity the strain rate is taken from (USAVG: the mean of the velocity after
/// the first correction and the final one), so the corrections are credited
/// Σ f·(v̄ − v_s) Δt as well: the share of the force the first correction cancelled
/// (USAVG: −½ f·δv₁ Δt).
fn grid_velocities(setup: &Setup, w: &mut Solver, dt: f64, touch: Option<&mut [Touch]>) {
    let through = setup.pass1_to_particles;
    let inv_dt = 1.0 / dt;
    // v̄ − v_s = c₁ δv₁ + c₂ δv₂ (+ a force term that is no correction's).
    let (c1, c2) = match setup.scheme {
        UpdateScheme::Usavg => (-0.5, 0.0),
        UpdateScheme::Usf => (-0.5, 0.5),
        UpdateScheme::Usl | UpdateScheme::Musl => (-0.5, -0.5),
    };
    let energies: Vec<[f64; 3]> = w
        .patches
        .par_iter_mut()
        .map(|patch| {
            let mut e = [0.0; 3];
            for (k, (n, kin)) in patch.nodes.iter().zip(patch.kin.iter_mut()).enumerate() {
                if n.m > 0.0 {
                    let v = n.p / n.m;
                    kin.a = if through {
                        (v - kin.a) * inv_dt
                    } else {
                        n.f / n.m
                    };
                    kin.v = v;
                    if let Some(l) = patch.ledger.get(k) {
                        let base = v - kin.a * dt;
                        let mid = 0.5 * n.m * (v + base);
                        let fdt = l.f * dt;
                        for kind in 0..2 {
                            let [d1, d2] = [l.dv[0][kind], l.dv[1][kind]];
                            e[kind] += mid.dot(d1 + d2) + fdt.dot(c1 * d1 + c2 * d2);
                        }
                        e[2] += 0.5 * n.m * (v.length_squared() - base.length_squared());
                    }
                } else {
                    *kin = Kin::default();
                }
            }
            e
        })
        .collect();
    if let Some(touch) = touch {
        for (t, e) in touch.iter_mut().zip(energies) {
            t.grid[0] += e[0];
            t.grid[1] += e[1];
            t.ke_grid += e[2];
        }
    }
    unfold(setup, w);
}

/// Grid to particles: velocity, position and (USL, USAVG's second half) stress.
fn g2p<K: Kernel>(
    setup: &Setup,
    p: &mut Particles,
    w: &mut Solver,
    (t, dt): (f64, f64),
    touch: &mut [Touch],
) -> Seen {
    let place = place(setup);
    let hi = setup.grid.hi();
    let musl = setup.scheme == UpdateScheme::Musl;
    if musl {
        w.next.resize(p.len(), DVec2::ZERO);
    }
    let stress = match setup.scheme {
        UpdateScheme::Usl => Some((t, dt)),
        UpdateScheme::Usavg => Some((t + 0.5 * dt, 0.5 * dt)),
        _ => None,
    };
    let models = stress.map(|window| prepared(setup, window));
    // Without a stress update the model is never called: one instantiation serves all.
    let none = ElasticStep {
        dt,
        bulk: 0.0,
        shear: 0.0,
        dth: 0.0,
    };
    let layout = &w.layout;
    let patches = &w.patches;
    let stencils = &w.stencils;
    let next = musl.then_some(&mut w.next[..]);
    let pts = split_points(p, layout, next);
    let seen: Vec<(u16, Seen)> = pts
        .into_par_iter()
        .enumerate()
        .map(|(k, pts)| {
            let mut pts = pts.expect("one piece per strip");
            let (b, strip, start, end) = layout.strips[k];
            let body = &setup.bodies[b as usize];
            let patch = &patches[b as usize];
            let view = (&patch.kin[..], patch.lo, patch.size[1]);
            let strip = strip as usize;
            let cache = &stencils[start..end];
            let (f, pts) = (setup.flip, &mut pts);
            use transfer::gather;
            let seen = match (body.motion, &models, setup.ledger) {
                (Motion::Prescribed(v), _, _) => {
                    transfer::move_rigid(&place, hi, v, dt, strip, pts)
                }
                (Motion::Free, Some(models), false) => with_model!(&models[b as usize], m => {
                    gather::<K, _, true, false>(&place, hi, m, dt, f, view, strip, pts, cache)
                }),
                (Motion::Free, Some(models), true) => with_model!(&models[b as usize], m => {
                    gather::<K, _, true, true>(&place, hi, m, dt, f, view, strip, pts, cache)
                }),
                (Motion::Free, None, false) => {
                    gather::<K, _, false, false>(&place, hi, &none, dt, f, view, strip, pts, cache)
                }
                (Motion::Free, None, true) => {
                    gather::<K, _, false, true>(&place, hi, &none, dt, f, view, strip, pts, cache)
                }
            };
            (b, seen)
        })
        .collect();
    for b in &mut w.bounds {
        *b = (DVec2::INFINITY, DVec2::NEG_INFINITY);
    }
    let mut all = Seen::empty();
    for (b, s) in seen {
        let bb = &mut w.bounds[b as usize];
        *bb = (bb.0.min(s.min), bb.1.max(s.max));
        touch[b as usize].ke_points += s.ke;
        all = all.merge(s);
    }
    all
}

/// MUSL: the updated particle momenta mapped back to the grid at the old positions.
fn remap<K: Kernel>(setup: &Setup, p: &Particles, w: &mut Solver) {
    w.patches.par_iter_mut().for_each(|patch| {
        for n in patch.nodes.iter_mut() {
            n.p = DVec2::ZERO;
        }
    });
    let src = source(p);
    for colour in 0..2 {
        let layout = &w.layout;
        let stencils = &w.stencils;
        views(&mut w.patches, layout, colour)
            .into_par_iter()
            .for_each(|(k, mut view)| {
                let (_, _, start, end) = layout.strips[k];
                let cache = &stencils[start..end];
                transfer::scatter_momentum::<K>(src, (start, end), &mut view, cache);
            });
    }
    fold(setup, w);
}

/// MUSL: stress from the re-mapped grid velocities over the time `window` (start,
/// length), then the
/// points move.
fn stress_last<K: Kernel>(setup: &Setup, p: &mut Particles, w: &mut Solver, window: (f64, f64)) {
    let models = prepared(setup, window);
    let layout = &w.layout;
    let patches = &w.patches;
    let stencils = &w.stencils;
    let pts = split_points(p, layout, Some(&mut w.next[..]));
    pts.into_par_iter().enumerate().for_each(|(k, pts)| {
        let mut pts = pts.expect("one piece per strip");
        let (b, _, start, end) = layout.strips[k];
        let body = &setup.bodies[b as usize];
        let patch = &patches[b as usize];
        match body.motion {
            Motion::Free => {
                let view = (&patch.kin[..], patch.lo, patch.size[1]);
                let cache = &stencils[start..end];
                with_model!(&models[b as usize], m => {
                    transfer::gather_stress::<K, _>(m, view, &mut pts, cache)
                });
            }
            Motion::Prescribed(_) => {
                let next = pts.next.take().expect("MUSL keeps the new positions apart");
                pts.pos.copy_from_slice(next);
            }
        }
    });
}

/// Points with weight at a node where their body's bond failed this step lose their bond.
fn forget_bonds<K: Kernel>(p: &mut Particles, w: &Solver) {
    let layout = &w.layout;
    split(&mut p.bond, layout, 1)
        .into_par_iter()
        .enumerate()
        .for_each(|(k, bond)| {
            let (b, _, start, end) = layout.strips[k];
            let patch = &w.patches[b as usize];
            if !patch.bond.is_empty() {
                crate::bond::forget::<K>(bond, &w.stencils[start..end], patch);
            }
        });
}

/// Decides whether the next step needs a re-sort, and stops on escaped points.
fn finish(setup: &Setup, s: &State, w: &mut Solver, seen: Seen) -> Result<(), Unstable> {
    if seen.escaped {
        let p = &s.particles;
        let lo = setup.grid.lo;
        let hi = setup.grid.hi();
        let i = (0..p.len())
            .find(|&i| !(p.pos[i].cmpge(lo).all() && p.pos[i].cmple(hi).all()))
            .unwrap_or(0);
        return Err(Unstable(format!(
            "point {} of body \"{}\" is at ({:.6e}, {:.6e}), outside the grid [{:?}, {:?}] or not finite",
            p.id[i],
            setup.bodies[p.body[i] as usize].name,
            p.pos[i].x,
            p.pos[i].y,
            lo.to_array(),
            hi.to_array()
        )));
    }
    w.resort |= seen.drifted;
    Ok(())
}
