//! Explosive-dispersal runs (`engine = "fem_dem"`): a charge modelled by grains-fem,
//! a particle ring by grains-dem, coupled by grains-couple through penalty contact at
//! the charge's edge (xue-2019 App. C). A scenario without a ring is a bare charge.
//!
//! The [`Blast`] simulation takes, every step, the largest step all three parts allow:
//! the charge's CFL step, the particles' own, and the penalty springs' as they are now.

pub mod assemble;
pub mod check;
pub mod checkpoint;
pub mod frames;
pub mod grains;
pub mod ledger;
pub mod models;
pub mod plots;
pub mod probes;
pub mod ranks;
pub mod run;
pub mod scenario;

use crate::dispersal::{Dispersing, Frame};
use crate::driver::{Clock, FrameKind, ParticleView, Simulation};
use crate::forces::Outside;
use crate::output::Capabilities;
use glam::DVec2;
use grains_analysis::ring::{self as ring_analysis, Disks, RingFigures, Rule};
use grains_couple::{coupled_step, coupled_step_with, Coupling, Ring};
use grains_dem::Reduce;
use grains_fem::diagnostics::{energies, fronts, Energies, Fronts};
use grains_fem::{Charge, FemSetup};
use std::borrow::Cow;

/// What a FEM–DEM run writes, and its defaults.
pub const CAPABILITIES: Capabilities = Capabilities {
    engine: "fem_dem",
    frames: 20,
    history: 1000,
    checkpoints: true,
    lammps_dump: false,
    grid: false,
};

/// The skin of the charge–particle candidates, in DEM skins: wide enough that they
/// last through most of the DEM list's life (a few more layers of grains to test each
/// step), where the DEM's own skin had them made again at every step late in a run.
pub const COUPLING_SKIN: f64 = 3.0;

/// Penetration of a particle into the charge, in radii, beyond which the contact has
/// failed (the particle is about to pass through the edge).
pub const RUNAWAY_PENETRATION: f64 = 0.9;

/// A running FEM–DEM simulation.
pub struct Blast {
    /// The charge's settings.
    pub fem: FemSetup,
    /// The charge.
    pub charge: Charge,
    /// The ring, if any.
    pub ring: Option<Ring>,
    /// The charge's centre, about which the ring is measured.
    pub centre: DVec2,
    /// Initial total energy of the charge (J/m).
    pub e0: f64,
    /// The step of the last step taken (before the first: the initial bound).
    pub dt: f64,
    /// Smallest and largest step taken.
    pub dt_range: (f64, f64),
    /// Largest penetration into the charge so far, in radii.
    pub max_penetration: f64,
    /// The particles' own step bound (s).
    pub dt_particles: f64,
    /// Forces on the ring from outside (none in a scenario run).
    pub outside: Outside,
    /// Fraction of the penalty springs' stable step.
    coupling_safety: f64,
    /// The smallest step the run accepts (s).
    dt_floor: f64,
    min_dt_ratio: f64,
    /// How the ring's layers are told apart, with its sector count and mean diameter.
    rule: Rule,
    sectors: usize,
    mean_d: f64,
    /// This rank's part when the run is spread over ranks (`ring` is then rank 0's
    /// view, whole after each gather).
    pub ranks: Option<Box<ranks::RingPart>>,
}

/// One sample of a blast run.
#[derive(Clone, Debug)]
pub struct BlastSample {
    /// The charge's energies.
    pub energies: Energies,
    /// The charge's burn and boundary.
    pub fronts: Fronts,
    /// The ring's radii, band and spall.
    pub ring: Option<RingFigures>,
    /// The ring's rotational kinetic energy (J/m), with the ledger.
    pub rotational: Option<f64>,
    /// The grains' energy ledger's figures, with the ledger.
    pub ledger: Option<grains_dem::EnergyLedger>,
}

impl Blast {
    /// Starts a run: the charge at rest, the ring in contact with it.
    pub fn new(s: &scenario::Scenario, a: assemble::Assembled) -> Self {
        let fem = a.fem;
        let mut charge = Charge::new(&fem, &a.mesh);
        let e0 = energies(&fem, &charge).total();
        let coupling_safety = s.run.coupling_safety;
        let (ring, dt_particles, mean_d) = match a.ring {
            Some(rp) => {
                let dt = rp.dt(coupling_safety);
                let coupling = Coupling::new(rp.stiffness, COUPLING_SKIN * rp.setup.skin);
                let mut ring = Ring::new(rp.setup, rp.particles, coupling, &mut charge);
                if s.analysis.energy_ledger {
                    // The ring's law is the linear one (a 2D scenario has no other),
                    // whose ledger is never refused.
                    let _ = grains_dem::ledger_sums::start(&ring.setup, &mut ring.state);
                }
                (Some(ring), dt, rp.mean_diameter)
            }
            None => (None, f64::INFINITY, 0.0),
        };
        let rule = rule(&s.analysis);
        let r_in = s.ring.as_ref().map_or(0.0, |r| r.inner_radius);
        let dt = (fem.safety * charge.dt_stable).min(dt_particles);
        Blast {
            dt_floor: s.run.min_dt_ratio * dt,
            min_dt_ratio: s.run.min_dt_ratio,
            centre: DVec2::from(s.charge.centre),
            e0,
            dt,
            dt_range: (f64::INFINITY, 0.0),
            max_penetration: 0.0,
            dt_particles,
            outside: Outside::default(),
            coupling_safety,
            sectors: ring_analysis::sectors(&rule, r_in, mean_d),
            rule,
            mean_d,
            fem,
            charge,
            ring,
            ranks: None,
        }
    }

    /// The charge's edge as the run steps it (on ranks, this rank's; its figures are
    /// every rank's).
    pub fn coupling(&self) -> Option<&Coupling> {
        match &self.ranks {
            Some(part) => Some(&part.coupling),
            None => self.ring.as_ref().map(|r| &r.coupling),
        }
    }

    /// Every grain of the ring in ascending id, over every rank.
    fn grains(&self) -> Option<grains::Grains> {
        let r = self.ring.as_ref()?;
        Some(match &self.ranks {
            Some(rp) => {
                let dec = &rp.part.dec;
                grains::gathered(rp.setup(), &rp.part.local, dec, &|i| dec.owns(i))
            }
            None => grains::gathered(&r.setup, &r.state, &grains_dem::Serial, &|_| true),
        })
    }

    /// The ring's figures now (radii, band and spall), if there is a ring: added in
    /// ascending id, the same on any rank count.
    pub fn ring_figures(&self) -> Option<RingFigures> {
        self.grains().map(|g| self.figures_of(&g))
    }

    fn figures_of(&self, g: &grains::Grains) -> RingFigures {
        let disks = Disks {
            pos: &g.pos,
            vel: &g.vel,
            radius: &g.radius,
            mass: &g.mass,
        };
        ring_analysis::measure(
            &self.rule,
            self.sectors,
            disks,
            self.centre,
            self.mean_d,
            &g.pressure,
        )
    }
}

/// The ring analysis's rule from the scenario's `[analysis]`.
pub fn rule(a: &scenario::AnalysisSpec) -> Rule {
    Rule {
        band_fraction: a.band_fraction,
        radial_bin: a.radial_bin,
        sectors: a.sectors,
        stressed_pressure: a.stressed_pressure,
    }
}

impl Blast {
    /// The ring's own fingerprint: on ranks, over every rank at the last gather.
    pub fn ring_hash(&self, r: &Ring) -> u64 {
        match &self.ranks {
            Some(rp) => rp.part.hash(),
            None => grains_dem::diagnostics::state_hash(&r.state),
        }
    }
}

impl Simulation for Blast {
    type Sample = BlastSample;

    fn clock(&self) -> Clock {
        Clock {
            time: self.charge.time,
            step: self.charge.step,
        }
    }

    fn advance(&mut self) -> Result<(), String> {
        let mut dt = (self.fem.safety * self.charge.dt_stable).min(self.dt_particles);
        if let Some(c) = self.coupling() {
            dt = dt.min(self.coupling_safety * c.stable_dt());
        }
        if dt < self.dt_floor {
            return Err(format!(
                "the time step fell to {dt:.4e} s, below run.min_dt_ratio = {} of the initial {:.4e} s \
                 (a crushed element or a runaway contact); lower run.min_dt_ratio to go on",
                self.min_dt_ratio,
                self.dt_floor / self.min_dt_ratio
            ));
        }
        self.dt_range = (self.dt_range.0.min(dt), self.dt_range.1.max(dt));
        self.dt = dt;
        let time = self.charge.time + dt;
        match self.ring.as_mut() {
            Some(r) if self.ranks.is_some() => {
                let rp = self.ranks.as_mut().expect("on ranks");
                let outside = &mut self.outside;
                let fem = (&self.fem, &mut self.charge);
                rp.advance(fem, dt, &mut |p| outside.apply(time, p), &mut r.state)
            }
            Some(r) if !self.outside.is_empty() => {
                let outside = &mut self.outside;
                coupled_step_with(&self.fem, &mut self.charge, r, dt, &mut |p| {
                    outside.apply(time, p)
                })
            }
            Some(r) => coupled_step(&self.fem, &mut self.charge, r, dt),
            None => grains_fem::step(&self.fem, &mut self.charge, dt),
        }
        .map_err(|b| b.to_string())?;
        if let Some(pen) = self.coupling().map(|c| c.max_penetration_ratio) {
            self.max_penetration = self.max_penetration.max(pen);
            if pen > RUNAWAY_PENETRATION {
                let c = self.coupling().expect("a ring");
                let at = c.deepest.map_or(String::new(), |d| {
                    format!(
                        " (particle {} at ({:.4e}, {:.4e}) m, on {} of a boundary edge {:.1} times its initial length)",
                        d.id,
                        d.pos.x,
                        d.pos.y,
                        if d.corner { "the corner node" } else { "the span" },
                        d.stretch
                    )
                });
                return Err(format!(
                    "a particle penetrated the charge's edge by {pen:.3} of its radius{at} \
                     (limit {RUNAWAY_PENETRATION}); raise coupling.stiffness_ratio or lower run.coupling_safety"
                ));
            }
        }
        Ok(())
    }

    fn sample(&mut self) -> BlastSample {
        // The ledger's figures are made here only (on ranks, by every rank at once).
        let ledger = match (&self.ranks, &self.ring) {
            (Some(rp), _) => rp.part.ledger_figures(),
            (None, Some(r)) => grains_dem::ledger_sums::figures(&r.state),
            (None, None) => None,
        };
        let grains = self.grains();
        BlastSample {
            energies: energies(&self.fem, &self.charge),
            fronts: fronts(&self.charge),
            ring: grains.as_ref().map(|g| self.figures_of(g)),
            rotational: grains.filter(|_| ledger.is_some()).map(|g| g.rotational),
            ledger,
        }
    }

    fn unstable(&self, _s: &BlastSample) -> Option<String> {
        let finite = |s: &grains_dem::State| {
            let p = &s.particles;
            let finite = p.pos.iter().chain(&p.vel).all(|v| v.is_finite());
            (!finite).then(|| "a particle position or velocity is not finite".to_string())
        };
        match &self.ranks {
            Some(rp) => rp.part.first(finite),
            None => finite(&self.ring.as_ref()?.state),
        }
    }

    fn particles(&self) -> ParticleView<'_> {
        match &self.ring {
            Some(r) => {
                let p = &r.state.particles;
                ParticleView {
                    id: &p.id,
                    pos: &p.pos,
                    vel: &p.vel,
                    radius: Cow::Borrowed(&p.radius),
                    mass: Cow::Owned((0..p.len()).map(|i| p.mass(i)).collect()),
                }
            }
            None => ParticleView {
                id: &[],
                pos: &[],
                vel: &[],
                radius: Cow::Borrowed(&[]),
                mass: Cow::Borrowed(&[]),
            },
        }
    }

    fn state_hash(&self) -> u64 {
        let mut h = grains_core::hash::Fnv1a::default();
        h.word(grains_fem::diagnostics::state_hash(&self.charge));
        if let Some(r) = &self.ring {
            h.word(self.ring_hash(r));
        }
        h.finish()
    }

    fn checkpoint(&self) -> Option<Vec<u8>> {
        // On several ranks rank 0 writes the ring it has just gathered (in the order a
        // serial run would hold it), so the file is the same on any rank count.
        if self.ranks.as_ref().is_some_and(|p| p.part.rank() != 0) {
            return None;
        }
        Some(self.snapshot())
    }

    fn gather(&mut self) {
        if let (Some(rp), Some(view)) = (self.ranks.as_mut(), self.ring.as_mut()) {
            rp.gather(&self.charge, view);
        }
    }

    fn frame_reads_whole(&self, kind: FrameKind) -> bool {
        // Each rank writes its piece of a regular frame; the snapshot maps are drawn
        // from every particle on rank 0.
        self.ranks.is_none() || kind != FrameKind::Regular
    }

    fn agree(&self, flag: bool) -> bool {
        match &self.ranks {
            Some(rp) => rp.part.dec.any(flag),
            None => flag,
        }
    }

    fn ranks(&self) -> usize {
        self.ranks.as_ref().map_or(1, |rp| rp.part.ranks())
    }
}

impl Dispersing for Blast {
    /// Every grain of every rank in ascending id (on ranks a collective: every rank
    /// calls it at the same point).
    fn dispersal_frame(&self) -> Frame {
        let mut f = match (&self.ring, &self.ranks) {
            (Some(_), Some(rp)) => {
                let dec = &rp.part.dec;
                grains::frame(rp.setup(), &rp.part.local, dec, &|i| dec.owns(i))
            }
            (Some(r), None) => grains::frame(&r.setup, &r.state, &grains_dem::Serial, &|_| true),
            (None, _) => Frame::default(),
        };
        f.time = self.charge.time;
        // As a finished run's analysis reads it from the mesh's frame.
        let c = self.centre;
        f.charge_radius = Some(
            self.charge
                .nodes
                .pos
                .iter()
                .map(|p| (*p - c).length())
                .fold(0.0, f64::max),
        );
        f
    }
}
