//! MPM runs (`engine = "mpm"`): the scenario, its assembly into a [`grains_mpm`]
//! set-up, the [`Mpm`] simulation, the body watch (impacts, samples, snapshots) and
//! outputs (history rows, frames, plots, figures, checks).

pub mod assemble;
pub mod cell;
pub mod check;
pub mod check_input;
pub mod concentric;
pub mod debond;
pub mod drive;
pub mod exchange;
pub mod frames;
pub mod packing;
pub mod plots;
pub mod probes;
pub mod reference;
pub mod response;
pub mod run;
pub mod scenario;
pub mod watch;

use crate::driver::{Clock, ParticleView, Simulation};
use crate::output::Capabilities;
use grains_mpm::diagnostics::{measure, Diagnostics};
use grains_mpm::{step, Motion, Setup, Solver, State};
use probes::{BodySample, Sample};
use std::borrow::Cow;

/// What an MPM run writes, and its defaults.
pub const CAPABILITIES: Capabilities = Capabilities {
    engine: "mpm",
    frames: 50,
    history: 2000,
    checkpoints: false,
    lammps_dump: false,
    grid: true,
};

/// A running MPM simulation.
pub struct Mpm {
    /// Engine configuration (read-only).
    pub setup: Setup,
    /// The points.
    pub state: State,
    /// Scratch space of the stages (its grid holds the last step's fields).
    pub solver: Solver,
    /// Time step (s).
    pub dt: f64,
    /// Also write the grid with every frame.
    pub grid_frames: bool,
    /// Rigid bodies whose velocity follows a table.
    pub drives: Vec<(usize, drive::VelocityTable)>,
    /// What the contact corrections exchanged so far.
    pub exchange: exchange::Exchange,
    /// The last sample, against which rotations are unwrapped.
    last: Option<MpmSample>,
}

/// One MPM sample: the diagnostics and what they mean per body (rotation unwrapped).
#[derive(Clone, Debug)]
pub struct MpmSample {
    /// Energies, momentum, per-body kinematics.
    pub diagnostics: Diagnostics,
    /// The same as the record keeps it.
    pub sample: Sample,
}

impl Mpm {
    /// The index of the body named `name` (a name the scenario's validation has seen).
    pub fn body(&self, name: &str) -> usize {
        self.setup
            .bodies
            .iter()
            .position(|b| b.name == name)
            .expect("validated body name")
    }

    /// The last sample taken, if any.
    pub fn last_sample(&self) -> Option<MpmSample> {
        self.last.clone()
    }

    /// Starts a run from assembled points.
    pub fn new(a: &assemble::Assembled, grid_frames: bool) -> Self {
        let mut state = State::new(&a.setup, a.particles.clone());
        let solver = Solver::new(&a.setup, &mut state);
        Mpm {
            setup: a.setup.clone(),
            state,
            solver,
            dt: a.dt,
            grid_frames,
            drives: a.drives.clone(),
            exchange: exchange::Exchange::new(a.setup.bodies.len()),
            last: None,
        }
    }
}

/// Mean in-plane stress (σ_xx + σ_yy)/2 of each body's points.
fn mean_stresses(p: &grains_mpm::Particles, ranges: &[(usize, usize)]) -> Vec<f64> {
    ranges
        .iter()
        .map(|&(a, b)| {
            let sum: f64 = p.stress[a..b].iter().map(|s| 0.5 * (s.xx + s.yy)).sum();
            sum / (b - a).max(1) as f64
        })
        .collect()
}

/// Unwraps each body's rotation against the previous sample.
fn to_sample(d: &Diagnostics, stress: &[f64], t: f64, prev: Option<&Sample>) -> Sample {
    let bodies = d
        .bodies
        .iter()
        .enumerate()
        .map(|(b, x)| {
            let angle = match prev {
                Some(p) => {
                    let last = p.bodies[b].angle;
                    let mut da = x.angle - last.rem_euclid(std::f64::consts::TAU);
                    da -= (da / std::f64::consts::TAU).round() * std::f64::consts::TAU;
                    last + da
                }
                None => x.angle,
            };
            BodySample {
                centre: x.centre,
                velocity: x.velocity,
                omega: x.omega,
                angle,
                mean_stress: stress[b],
                debonded: x.lengths.debonded,
                surface: x.lengths.surface,
                ..Default::default()
            }
        })
        .collect();
    Sample {
        t,
        energy: d.total(),
        balance: d.balance(),
        dissipated: d.dissipated,
        thermal_work: d.thermal_work,
        momentum: d.momentum,
        bodies,
        ..Default::default()
    }
}

impl Simulation for Mpm {
    type Sample = MpmSample;

    fn clock(&self) -> Clock {
        Clock {
            time: self.state.time,
            step: self.state.step,
        }
    }

    fn advance(&mut self) -> Result<(), String> {
        for (b, table) in &self.drives {
            let v = table.over_step(self.state.time, self.dt);
            self.setup.bodies[*b].motion = Motion::Prescribed(v);
        }
        step(&self.setup, &mut self.state, &mut self.solver, self.dt).map_err(|e| e.to_string())?;
        self.exchange.step(&self.setup, &self.state.touch, self.dt);
        Ok(())
    }

    fn sample(&mut self) -> MpmSample {
        let ranges = &self.solver.layout().bodies;
        let d = measure(&self.setup, &self.state.particles, ranges);
        let stress = mean_stresses(&self.state.particles, ranges);
        let prev = self.last.as_ref().map(|s| &s.sample);
        let forces = self.exchange.forces(self.state.time);
        let mut sample = to_sample(&d, &stress, self.state.time, prev);
        let x = &self.exchange;
        for (b, s) in sample.bodies.iter_mut().enumerate() {
            (s.force, s.displacement) = (forces[b], x.displacement[b]);
            match self.setup.materials[self.setup.bodies[b].material] {
                grains_mpm::Material::J2Plastic { .. } => sample.plastic += d.bodies[b].dissipated,
                grains_mpm::Material::Maxwell { .. } => sample.viscous += d.bodies[b].dissipated,
                _ => {}
            }
        }
        (sample.friction, sample.bond, sample.work) = (x.friction, x.bond, x.work);
        sample.transfer = x.transfer;
        let s = MpmSample {
            diagnostics: d,
            sample,
        };
        self.last = Some(s.clone());
        s
    }

    fn unstable(&self, s: &MpmSample) -> Option<String> {
        let d = &s.diagnostics;
        if !d.finite {
            return Some("a position, velocity or stress is not finite (NaN or infinity)".into());
        }
        let c = grains_mpm::timestep::wave_speed(&self.setup);
        let cfl = (c + d.max_speed) * self.dt / self.setup.grid.h;
        (cfl > 1.0).then(|| {
            format!(
                "CFL breach: (c + |v|max)·Δt/h = {cfl:.3} > 1 with |v|max = {:.4e} m/s; lower run.dt or run.safety",
                d.max_speed
            )
        })
    }

    fn particles(&self) -> ParticleView<'_> {
        let p = &self.state.particles;
        ParticleView {
            id: &p.id,
            pos: &p.pos,
            vel: &p.vel,
            radius: Cow::Owned(
                (0..p.len())
                    .map(|i| (p.volume(i) / std::f64::consts::PI).sqrt())
                    .collect(),
            ),
            mass: Cow::Borrowed(&p.mass),
        }
    }

    fn state_hash(&self) -> u64 {
        grains_mpm::diagnostics::state_hash(&self.state.particles)
    }
}
