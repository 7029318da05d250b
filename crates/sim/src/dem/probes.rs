//! Recorders that watch a few particles during a run and turn what they saw into the
//! scenario's checks: binary collisions (restitution, contact time) and wall impacts
//! (rigid-body impulse theory) under the linear law; under the granular law the
//! collision watch both dimensions share ([`crate::collision`]). They only read the
//! particles they watch, through [`Dem::watched`] (in ascending id, on every rank of a
//! run spread over ranks), so they see the same bits on any rank count.

use super::scenario::CheckSpec;
use super::Dem;
use crate::collision::dim2::Watch;
use crate::driver::{Observer, Report, Status};
use glam::DVec2;
use grains_core::checks::Check;
use grains_dem::{PairTable, Particles, Setup, State};

#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
enum Phase {
    #[default]
    Before,
    During,
    After,
}

/// What a pair of particles did in their first collision.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
struct Collision {
    ids: [u32; 2],
    at: [usize; 2],
    phase: Phase,
    prev: (f64, f64),
    vn_before: f64,
    vn_after: f64,
    start: f64,
    end: f64,
}

/// What one particle did in its first impact on one wall.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
struct Impact {
    id: u32,
    wall: usize,
    at: usize,
    phase: Phase,
    before: (DVec2, f64),
    after: (DVec2, f64),
    normal: DVec2,
}

/// All recorders a scenario's checks need.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Probes {
    collisions: Vec<Collision>,
    impacts: Vec<Impact>,
    /// The collision watch of each check (`None` for other kinds; a checkpoint's TOML has
    /// no null, so a list of at most one).
    #[serde(default)]
    watches: Vec<Vec<Watch>>,
}

fn zero_crossing(t0: f64, o0: f64, t1: f64, o1: f64) -> f64 {
    if o1 == o0 {
        t1
    } else {
        t0 + (t1 - t0) * (0.0 - o0) / (o1 - o0)
    }
}

impl Probes {
    /// Recorders for the given checks.
    pub fn new(setup: &Setup, checks: &[CheckSpec]) -> Self {
        let mut p = Probes::default();
        for c in checks {
            match c {
                CheckSpec::Restitution { particles, .. }
                | CheckSpec::ContactTime { particles, .. } => {
                    if !p.collisions.iter().any(|k| k.ids == *particles) {
                        p.collisions.push(Collision {
                            ids: *particles,
                            at: [0, 0],
                            phase: Phase::Before,
                            prev: (0.0, f64::NEG_INFINITY),
                            vn_before: f64::NAN,
                            vn_after: f64::NAN,
                            start: f64::NAN,
                            end: f64::NAN,
                        });
                    }
                }
                CheckSpec::ImpactTangentialVelocity { particle, wall, .. }
                | CheckSpec::ImpactAngularVelocity { particle, wall, .. } => {
                    let w = setup
                        .walls
                        .iter()
                        .position(|x| &x.name == wall)
                        .unwrap_or(0);
                    if !p.impacts.iter().any(|k| k.id == *particle && k.wall == w) {
                        p.impacts.push(Impact {
                            id: *particle,
                            wall: w,
                            at: 0,
                            phase: Phase::Before,
                            before: (DVec2::NAN, f64::NAN),
                            after: (DVec2::NAN, f64::NAN),
                            normal: DVec2::NAN,
                        });
                    }
                }
                CheckSpec::WallForceOverWeight { .. } | CheckSpec::Collision { .. } => {}
            }
        }
        p
    }

    /// True when nothing needs watching step by step.
    pub fn is_empty(&self) -> bool {
        self.collisions.is_empty() && self.impacts.is_empty() && self.watches.is_empty()
    }

    /// The particles still watched, by id (a collision or impact over needs none).
    pub fn ids(&self) -> Vec<u32> {
        let pairs = self.collisions.iter().filter(|c| c.phase != Phase::After);
        let impacts = self.impacts.iter().filter(|m| m.phase != Phase::After);
        let watches = self.watches.iter().flatten().flat_map(Watch::ids);
        let mut ids: Vec<u32> = pairs.flat_map(|c| c.ids).collect();
        ids.extend(impacts.map(|m| m.id).chain(watches));
        ids
    }

    /// Finds the watched particles in `p` (a view in ascending id: [`Dem::watched`]).
    fn locate(&mut self, p: &Particles) {
        let find = |id: u32| p.id.binary_search(&id).unwrap_or(0);
        for c in &mut self.collisions {
            c.at = [find(c.ids[0]), find(c.ids[1])];
        }
        for m in &mut self.impacts {
            m.at = find(m.id);
        }
    }

    /// Looks at the particles `p` ([`Probes::ids`] at least, in ascending id) after the
    /// step that ended at `time`.
    pub fn observe(&mut self, setup: &Setup, p: &Particles, time: f64) {
        for w in self.watches.iter_mut().flatten() {
            w.step(setup, p, time);
        }
        self.locate(p);
        for c in self
            .collisions
            .iter_mut()
            .filter(|c| c.phase != Phase::After)
        {
            let [a, b] = c.at;
            let d = setup.domain.min_image(p.pos[b] - p.pos[a]);
            let dist = d.length();
            let overlap = p.radius[a] + p.radius[b] - dist;
            let vn = (p.vel[a] - p.vel[b]).dot(d / dist);
            match c.phase {
                Phase::Before if overlap > 0.0 => {
                    c.start = zero_crossing(c.prev.0, c.prev.1, time, overlap);
                    c.phase = Phase::During;
                }
                Phase::Before => c.vn_before = vn,
                Phase::During if overlap <= 0.0 => {
                    c.end = zero_crossing(c.prev.0, c.prev.1, time, overlap);
                    c.vn_after = vn;
                    c.phase = Phase::After;
                }
                _ => {}
            }
            c.prev = (time, overlap);
        }
        for m in self.impacts.iter_mut().filter(|m| m.phase != Phase::After) {
            let i = m.at;
            let Some(touch) = setup.walls[m.wall].shape.nearest(p.pos[i]) else {
                continue;
            };
            let overlap = p.radius[i] - touch.distance;
            match m.phase {
                Phase::Before if overlap > 0.0 => {
                    m.normal = touch.normal;
                    m.phase = Phase::During;
                }
                Phase::Before => m.before = (p.vel[i], p.omega[i]),
                Phase::During if overlap <= 0.0 => {
                    m.after = (p.vel[i], p.omega[i]);
                    m.phase = Phase::After;
                }
                _ => {}
            }
        }
    }

    /// Turns the recordings into checks, in the order the scenario lists them: `p` is
    /// every particle in ascending id ([`Dem::watched`]), `s` the run's state (its
    /// wall loads).
    pub fn checks(
        &mut self,
        setup: &Setup,
        (p, s): (&Particles, &State),
        specs: &[CheckSpec],
        restitution: &PairTable<Option<f64>>,
    ) -> Vec<Check> {
        self.locate(p);
        let mut out = Vec::new();
        for (k, spec) in specs.iter().enumerate() {
            let (name, tol) = (spec.name(), spec.tolerance());
            match spec {
                CheckSpec::Restitution { particles, .. }
                | CheckSpec::ContactTime { particles, .. } => {
                    let c = self
                        .collisions
                        .iter()
                        .find(|c| c.ids == *particles)
                        .expect("recorder");
                    let [a, b] = c.at;
                    let m_eff = 1.0 / (p.inv_mass[a] + p.inv_mass[b]);
                    let pair = setup
                        .pairs
                        .get(p.material[a] as usize, p.material[b] as usize);
                    let (measured, expected) = match spec {
                        CheckSpec::Restitution { .. } => {
                            (-c.vn_after / c.vn_before, pair.restitution(m_eff))
                        }
                        _ => (c.end - c.start, pair.contact_time(m_eff)),
                    };
                    let mut check = Check::relative(name, measured, expected, tol);
                    if c.phase != Phase::After {
                        check = check.with_note("the collision did not complete within the run");
                    }
                    out.push(check);
                }
                CheckSpec::ImpactTangentialVelocity { particle, .. }
                | CheckSpec::ImpactAngularVelocity { particle, .. } => {
                    let m = self
                        .impacts
                        .iter()
                        .find(|m| m.id == *particle)
                        .expect("recorder");
                    let i = m.at;
                    let (v0, w0) = m.before;
                    let n = m.normal;
                    let t = n.perp();
                    let r = p.radius[i];
                    let f = setup.materials[p.material[i] as usize].inertia_factor;
                    let pair = setup.wall_pair(m.wall, p.material[i] as usize);
                    let mass = p.mass(i);
                    let e = pair.restitution(mass);
                    let vn = v0.dot(n);
                    let slip = v0.dot(t) + r * w0;
                    // Rigid-body impulse theory: Coulomb-limited tangential impulse, or the
                    // impulse that stops sliding if that is smaller (1 + 1/f: the contact
                    // point's inverse mass with rotation).
                    let j = -slip.signum()
                        * (pair.mu * (1.0 + e) * vn).min(slip.abs() / (1.0 + 1.0 / f));
                    let (measured, expected) = match spec {
                        CheckSpec::ImpactTangentialVelocity { .. } => {
                            (m.after.0.dot(t), v0.dot(t) + j)
                        }
                        _ => (m.after.1, w0 + j / (f * r)),
                    };
                    let mut check = Check::relative(name, measured, expected, tol);
                    if m.phase != Phase::After {
                        check = check.with_note("the impact did not complete within the run");
                    }
                    out.push(check);
                }
                CheckSpec::Collision { measure, .. } => {
                    out.push(match self.watches.get(k).and_then(|w| w.first()) {
                        Some(w) => w.check(name, *measure, tol, setup, p, restitution),
                        None => Check::relative(name, f64::NAN, 1.0, tol)
                            .with_note("the particle has no partner"),
                    });
                }
                CheckSpec::WallForceOverWeight { wall, .. } => {
                    let w = setup
                        .walls
                        .iter()
                        .position(|x| &x.name == wall)
                        .expect("validated");
                    let g = setup.gravity;
                    let weight: f64 = (0..p.len()).map(|i| p.mass(i)).sum::<f64>() * g.length();
                    let along = s.wall_loads[w].force.dot(g.normalize());
                    out.push(Check::relative(name, along / weight, 1.0, tol));
                }
            }
        }
        out
    }
}

/// The scenario's checks: the recorders, watching every step, and the specs they serve.
pub struct CheckObserver {
    /// The recorders.
    pub probes: Probes,
    /// The checks, in the scenario's order.
    pub specs: Vec<CheckSpec>,
    /// The restitution each pair's law is built for, where it takes one.
    pub restitution: PairTable<Option<f64>>,
}

impl CheckObserver {
    /// Recorders for `specs`, having seen the initial state, `restitution` each pair's
    /// target.
    pub fn new(sim: &Dem, specs: &[CheckSpec], restitution: PairTable<Option<f64>>) -> Self {
        let mut probes = Probes::new(&sim.setup, specs);
        if specs
            .iter()
            .any(|c| matches!(c, CheckSpec::Collision { .. }))
        {
            probes.watches = specs
                .iter()
                .map(|c| match c {
                    CheckSpec::Collision {
                        particle,
                        partner,
                        wall,
                        ..
                    } => {
                        let at = (&sim.state.particles, sim.state.time);
                        Watch::of(&sim.setup, at, *particle, *partner, wall.as_deref())
                            .into_iter()
                            .collect()
                    }
                    _ => Vec::new(),
                })
                .collect();
        }
        // Every rank holds the whole start here.
        let ids = probes.ids();
        let p = sim.watched(|id| ids.contains(&id));
        probes.observe(&sim.setup, &p, sim.state.time);
        CheckObserver {
            probes,
            specs: specs.to_vec(),
            restitution,
        }
    }
}

impl Observer<Dem> for CheckObserver {
    fn on_step(&mut self, sim: &Dem) {
        let ids = self.probes.ids();
        if ids.is_empty() {
            return;
        }
        let p = sim.watched(|id| ids.contains(&id));
        self.probes.observe(&sim.setup, &p, sim.state.time);
    }

    fn on_end(&mut self, sim: &Dem, _status: &Status, report: &mut Report) -> anyhow::Result<()> {
        if self.specs.is_empty() {
            return Ok(());
        }
        let p = sim.watched(|_| true);
        let at = (&p, &sim.state);
        let checks = self
            .probes
            .checks(&sim.setup, at, &self.specs, &self.restitution);
        report.checks.extend(checks);
        Ok(())
    }

    fn save(&self) -> Option<(&'static str, toml::Value)> {
        toml::Value::try_from(&self.probes)
            .ok()
            .map(|v| ("probes", v))
    }

    fn restore(&mut self, state: toml::Value) -> anyhow::Result<()> {
        self.probes = state.try_into()?;
        Ok(())
    }
}
