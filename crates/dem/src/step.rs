//! One DEM time step: `kick_drift → neighbours (kept, or rebuilt once a particle may have
//! come within reach of one not listed: [`crate::verlet`]) → pair_contacts →
//! [post_force] → walls_gather_kick`.
//!
//! Outside forces (a coupled solid, a field) enter through [`Hooks`], as LAMMPS fixes do
//! through `post_force`: the step itself is never copied to add them.

use crate::comm::{Exchange, Reduce, Serial};
use crate::forces::pair_contacts;
use crate::integrate::{kick_drift, wall_loads, walls_gather_kick, Drift, WallLoad};
use crate::ledger_sums::LedgerSums;
use crate::math::Components;
use crate::math::Vector;
use crate::neighbours::ContactList;
use crate::particles::Particles;
use crate::setup::Setup;
use crate::walls::Pose;
use crate::wavefront;

/// Everything that evolves during a run.
#[derive(Clone, Debug, Default)]
pub struct State {
    /// The particles.
    pub particles: Particles,
    /// Neighbour list and contact history.
    pub contacts: ContactList,
    /// Load on each wall at the last force evaluation.
    pub wall_loads: Vec<WallLoad>,
    /// Simulated time (s).
    pub time: f64,
    /// Steps taken.
    pub step: u64,
    /// The contacts' energy ledger, kept while `Some` (see [`crate::ledger_sums`]): each
    /// particle's running ledger is in [`Particles::ledger`]; this holds the exact
    /// sums of what particles that left the run took with them (none does yet: nothing
    /// removes particles), carried by gathers and checkpoints.
    pub ledger: Option<LedgerSums>,
    /// Where each wall has got to ([`crate::walls::advance_walls`]).
    pub walls: Vec<Pose>,
}

impl State {
    /// Wraps particles into a state and evaluates the initial forces (without advancing
    /// any tangential spring), so the first step starts from consistent forces.
    pub fn new(setup: &Setup, particles: Particles) -> Self {
        let mut s = State {
            particles,
            walls: crate::walls::poses(setup),
            ..Default::default()
        };
        s.contacts.rebuild(setup, &mut s.particles);
        pair_contacts(setup, &mut s.particles, &mut s.contacts, 0.0, false);
        let parts = walls_gather_kick(setup, &mut s.particles, &mut s.contacts, 0.0, 0.0, None);
        s.wall_loads = wall_loads(&parts, &crate::comm::Serial);
        s
    }
}

/// What rides on a step from outside the particle system. Every method has a default
/// that does nothing, so a plain run passes [`NoHooks`].
pub trait Hooks {
    /// The box the neighbour cell grid spans along non-periodic axes when the list is
    /// rebuilt (lower and upper corner); default the domain's.
    fn grid_box(&mut self, setup: &Setup, _particles: &Particles) -> (Vector, Vector) {
        (setup.domain.lo, setup.domain.hi)
    }

    /// After the neighbour stage, with the particles in their (possibly new) order;
    /// `change` says whether the list was rebuilt (and the particles re-sorted), or kept
    /// although some particle has moved more than skin/2 since the rebuild;
    /// `displacement` is the largest distance of a particle from where it was at the
    /// last rebuild (0 right after one).
    fn post_neighbour(&mut self, _particles: &Particles, _change: ListChange, _displacement: f64) {}

    /// After the pair forces and before walls and the closing kick: add outside forces
    /// to `particles.force` (and torques to `particles.torque`).
    fn post_force(&mut self, _particles: &mut Particles) {}

    /// Whether [`Hooks::post_force`] (or [`Hooks::post_force_on`]) may add a force or a
    /// torque; default yes. A step whose hooks add none gathers each chunk's reactions
    /// as soon as the passes that write them are done ([`crate::wavefront`]).
    fn adds_forces(&self) -> bool {
        true
    }

    /// [`Hooks::post_force`] on one rank of several: `comm` reduces over the ranks and
    /// tells which stored particles are this rank's own (a ghost's force is its owner's
    /// to compute; the ghost takes it at the end of the step). Default:
    /// [`Hooks::post_force`], which serves hooks whose forces need nothing of the
    /// other ranks.
    fn post_force_on(&mut self, particles: &mut Particles, _comm: &dyn Exchange) {
        self.post_force(particles);
    }
}

/// What the neighbour stage of a step did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ListChange {
    /// Every particle is within skin/2 of where it was at the last rebuild.
    Kept,
    /// The list is still valid in its expanding frame ([`crate::verlet`]), but some
    /// particle has moved more than skin/2 from where it was at the rebuild.
    Moved,
    /// The list was rebuilt and the particles re-sorted.
    Rebuilt,
}

/// No outside forces.
pub struct NoHooks;

impl Hooks for NoHooks {
    fn adds_forces(&self) -> bool {
        false
    }
}

/// Advances the state by one time step `dt`.
pub fn step(setup: &Setup, s: &mut State, dt: f64) {
    step_with(setup, s, dt, &mut NoHooks);
}

/// Advances the state by one time step `dt`, with outside forces from `hooks`.
pub fn step_with<H: Hooks>(setup: &Setup, s: &mut State, dt: f64, hooks: &mut H) {
    step_on(setup, s, dt, hooks, &mut Serial);
}

/// Advances the state by one time step `dt`, with outside forces from `hooks`, its
/// global figures reduced and its particles exchanged through `comm` ([`crate::comm`];
/// [`Serial`] in a run on one process).
pub fn step_on<H: Hooks, C: Exchange>(
    setup: &Setup,
    s: &mut State,
    dt: f64,
    hooks: &mut H,
    comm: &mut C,
) {
    let list = &s.contacts;
    let frame = list.frame.as_ref().map(|f| (f, &list.normal_at_build[..]));
    let mut drift = kick_drift(setup, &mut s.particles, &list.pos_at_build, frame, dt);
    if comm.ranks() > 1 {
        drift = global_drift(setup, drift, comm);
    }
    let (change, displacement) = neighbours(setup, s, &drift, hooks, comm);
    hooks.post_neighbour(&s.particles, change, displacement);
    let ledger = s.ledger.is_some();
    let fused = !ledger && !hooks.adds_forces() && wavefront::applies(&s.particles, &s.contacts);
    if !fused {
        pair_contacts(setup, &mut s.particles, &mut s.contacts, dt, ledger);
        hooks.post_force_on(&mut s.particles, &*comm);
    }
    let parts = match ledger {
        false if fused => {
            wavefront::pair_contacts_gather_kick(setup, &mut s.particles, &mut s.contacts, dt)
        }
        false => walls_gather_kick(setup, &mut s.particles, &mut s.contacts, dt, 0.5 * dt, None),
        true => {
            let list = &mut s.contacts;
            let mut rows = std::mem::take(&mut list.ledger_rows);
            rows.resize(s.particles.len(), Default::default());
            let p = &mut s.particles;
            let loads = walls_gather_kick(setup, p, list, dt, 0.5 * dt, Some(&mut rows));
            crate::ledger_sums::wall_pass(&mut p.ledger, &rows);
            list.ledger_rows = rows;
            loads
        }
    };
    s.wall_loads = wall_loads(&parts, &*comm);
    comm.refresh(setup, &mut s.particles);
    s.time += dt;
    s.step += 1;
}

/// The neighbour stage: keeps the list while it is still valid, else rebuilds it;
/// returns what it did and the largest displacement since the list's build.
fn neighbours<H: Hooks, C: Exchange>(
    setup: &Setup,
    s: &mut State,
    drift: &Drift,
    hooks: &mut H,
    comm: &mut C,
) -> (ListChange, f64) {
    if drift.moved && !drift.in_frame {
        comm.migrate(setup, s);
        let bounds = hooks.grid_box(setup, &s.particles);
        s.contacts.rebuild_within(setup, bounds, &mut s.particles);
        comm.rebuilt(setup, s);
        return (ListChange::Rebuilt, 0.0);
    }
    let list = &mut s.contacts;
    // Any frame will do for the next step's test; this one follows the particles.
    let mut n = [comm.owned(&s.particles) as u64];
    if comm.ranks() > 1 {
        comm.sum_u64(&mut n);
    }
    let n = n[0] as usize;
    if let Some(f) = list.frame.as_mut() {
        *f = f.estimate(&drift.sums, n);
    }
    let change = if drift.moved {
        ListChange::Moved
    } else {
        ListChange::Kept
    };
    (change, drift.displacement)
}

/// The rebuild test over every rank: the list is rebuilt everywhere when any particle
/// anywhere has moved too far, and the frame is estimated from every particle.
fn global_drift<C: Reduce>(setup: &Setup, d: Drift, comm: &C) -> Drift {
    let mut flags = [d.moved as u64, !d.in_frame as u64];
    comm.sum_u64(&mut flags);
    let mut top = [d.displacement, d.sums.radial[1], -d.sums.radial[0]];
    comm.max(&mut top);
    // The two largest residuals anywhere bound every pair, across ranks too.
    let all = comm.gather(d.residuals.iter().map(|r| r.to_bits()).collect());
    let mut res = [0.0f64; 2];
    for r in all.into_iter().map(f64::from_bits) {
        if r > res[1] {
            res = if r > res[0] { [r, res[0]] } else { [res[0], r] };
        }
    }
    let mut sums: Vec<f64> = (0..Vector::N)
        .map(|a| d.sums.displacement.get(a))
        .chain((0..Vector::N).map(|a| d.sums.normal.get(a)))
        .collect();
    comm.sum(&mut sums);
    let mut out = d;
    out.moved = flags[0] > 0;
    out.in_frame = flags[1] == 0 && res[0].sqrt() + res[1].sqrt() <= setup.skin;
    out.displacement = top[0];
    out.residuals = res;
    out.sums.radial = [-top[2], top[1]];
    out.sums.displacement = Vector::from_slice(&sums);
    out.sums.normal = Vector::from_slice(&sums[Vector::N..]);
    out
}
