//! One collision check's watch and its validation, written in the engine's names
//! (`super::engine`: `grains-dem` or `grains-dem3d`).

use super::super::{Measure, HERTZ_TIME};
use super::engine::diagnostics::index_of;
use super::engine::granular::Normal;
use super::engine::math::{AngVector, TangentOps, Vector};
use super::engine::{PairTable, Particles, Setup};
use grains_core::checks::Check;
use grains_core::input::InputError;
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
enum Phase {
    Before,
    In,
    After,
}

/// What the particle collides with.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub enum Partner {
    /// Another particle, by id.
    Particle(u32),
    /// A wall, by index.
    Wall(usize),
}

/// One collision, as it went.
#[derive(Clone, Debug, Serialize, Deserialize)]
struct Impact {
    phase: Phase,
    gap: f64,
    time: f64,
    /// Unit normal from the particle towards its partner, at first contact.
    normal: Vector,
    /// Relative velocity before and after.
    before: Vector,
    after: Vector,
    omega_after: AngVector,
    t_in: f64,
    t_out: f64,
    overlap: f64,
    force: f64,
}

/// The first collision of a particle (by id) with its partner, watched step by step.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Watch(pub u32, pub Partner, Impact);

/// The geometry of a collision now: (gap, unit normal towards the partner, relative
/// velocity).
fn geometry(
    setup: &Setup,
    p: &Particles,
    i: usize,
    partner: Partner,
) -> Option<(f64, Vector, Vector)> {
    match partner {
        Partner::Particle(id) => {
            let j = index_of(p, id)?;
            let d = setup.domain.min_image(p.pos[j] - p.pos[i]);
            let dist = d.length();
            Some((
                dist - p.radius[i] - p.radius[j],
                d / dist,
                p.vel[i] - p.vel[j],
            ))
        }
        Partner::Wall(w) => {
            let t = setup.walls[w].shape.nearest(p.pos[i])?;
            Some((t.distance - p.radius[i], t.normal, p.vel[i]))
        }
    }
}

impl Watch {
    /// The watch of a check's `particle` and its partner (validated): another particle
    /// or the wall named `wall`, from the particles `p` at `time`.
    pub fn of(
        setup: &Setup,
        (p, time): (&Particles, f64),
        particle: u32,
        partner: Option<u32>,
        wall: Option<&str>,
    ) -> Option<Self> {
        let to = match partner {
            Some(j) => Partner::Particle(j),
            None => Partner::Wall(
                setup
                    .walls
                    .iter()
                    .position(|x| Some(x.name.as_str()) == wall)?,
            ),
        };
        Watch::new(setup, (p, time), particle, to)
    }

    /// The watch of particle `id`'s collision with `partner`, from the particles `p` at
    /// `time`.
    pub fn new(
        setup: &Setup,
        (p, time): (&Particles, f64),
        id: u32,
        partner: Partner,
    ) -> Option<Self> {
        let (gap, normal, v) = geometry(setup, p, index_of(p, id)?, partner)?;
        let impact = Impact {
            phase: if gap < 0.0 { Phase::In } else { Phase::Before },
            gap,
            time,
            normal,
            before: v,
            after: v,
            omega_after: AngVector::default(),
            t_in: time,
            t_out: f64::NAN,
            overlap: 0.0,
            force: 0.0,
        };
        Some(Watch(id, partner, impact))
    }

    /// The particles it watches, by id (none once the collision is over).
    pub fn ids(&self) -> Vec<u32> {
        let Watch(id, partner, m) = self;
        match (m.phase, partner) {
            (Phase::After, _) => Vec::new(),
            (_, Partner::Particle(j)) => vec![*id, *j],
            (_, Partner::Wall(_)) => vec![*id],
        }
    }

    /// Looks at the particles `p` (those of [`Watch::ids`] at least) after the step
    /// that ended at `time`.
    pub fn step(&mut self, setup: &Setup, p: &Particles, time: f64) {
        let Watch(id, partner, m) = self;
        if m.phase == Phase::After {
            return;
        }
        let Some(i) = index_of(p, *id) else {
            return;
        };
        let Some((gap, normal, v)) = geometry(setup, p, i, *partner) else {
            return;
        };
        // Where the gap crossed zero within the step just taken.
        let crossing = m.time + (time - m.time) * m.gap / (m.gap - gap);
        match m.phase {
            Phase::Before if gap < 0.0 => {
                (m.phase, m.t_in, m.normal) = (Phase::In, crossing, normal);
            }
            Phase::Before => m.before = v,
            Phase::In if gap >= 0.0 => {
                (m.phase, m.t_out, m.after) = (Phase::After, crossing, v);
                m.omega_after = p.omega[i];
            }
            _ => {}
        }
        if m.phase == Phase::In {
            m.overlap = m.overlap.max(-gap);
            m.force = m.force.max(p.force[i].length());
        }
        (m.gap, m.time) = (gap, time);
    }

    /// The check `name` of `measure` (validated by [`validate`]) within relative `tol`,
    /// `restitution` each pair's target.
    pub fn check(
        &self,
        name: &str,
        measure: Measure,
        tol: f64,
        setup: &Setup,
        p: &Particles,
        restitution: &PairTable<Option<f64>>,
    ) -> Check {
        let Watch(id, partner, m) = self;
        let i = index_of(p, *id).expect("ids stay");
        let mi = p.material[i] as usize;
        let (mj, r_eff, m_eff) = match *partner {
            Partner::Particle(jd) => {
                let j = index_of(p, jd).expect("ids stay");
                let (ri, rj) = (p.radius[i], p.radius[j]);
                (
                    p.material[j] as usize,
                    ri * rj / (ri + rj),
                    1.0 / (p.inv_mass[i] + p.inv_mass[j]),
                )
            }
            Partner::Wall(w) => (
                setup.walls[w].material.map_or(mi, |k| k as usize),
                p.radius[i],
                p.mass(i),
            ),
        };
        let n = m.normal;
        let vn = m.before.dot(n);
        let e = -m.after.dot(n) / vn;
        let law = || setup.granular.as_ref().expect("validated").get(mi, mj);
        let (measured, expected) = match measure {
            Measure::MaxOverlap | Measure::PeakForce | Measure::ContactTime => {
                let e_star = 0.75 * law().kn;
                let delta = (15.0 * m_eff * vn * vn / (16.0 * e_star * r_eff.sqrt())).powf(0.4);
                match measure {
                    Measure::MaxOverlap => (m.overlap, delta),
                    Measure::PeakForce => {
                        (m.force, 4.0 / 3.0 * e_star * r_eff.sqrt() * delta.powf(1.5))
                    }
                    _ => (m.t_out - m.t_in, HERTZ_TIME * delta / vn),
                }
            }
            Measure::Restitution => (e, restitution.get(mi, mj).unwrap_or(f64::NAN)),
            Measure::TangentialVelocity | Measure::AngularVelocity => {
                let impulse = law().mu * (1.0 + e) * vn;
                let tangential = |v: Vector| (v - v.dot(n) * n).length();
                if measure == Measure::TangentialVelocity {
                    (tangential(m.after), tangential(m.before) - impulse)
                } else {
                    let k = setup.materials[mi].inertia_factor;
                    (m.omega_after.norm() * p.radius[i], impulse / k)
                }
            }
        };
        let c = Check::relative(name, measured, expected, tol);
        if m.phase == Phase::After {
            c
        } else {
            c.with_note("the collision did not end within the run")
        }
    }
}

/// Checks the collision check `check[k]`: the particle, exactly one of its partner and
/// its wall, and the law the measure's value needs; returns the partner.
#[allow(clippy::too_many_arguments)]
pub fn validate(
    k: usize,
    measure: Measure,
    particle: u32,
    partner: Option<u32>,
    wall: Option<&str>,
    setup: &Setup,
    p: &Particles,
    restitution: &PairTable<Option<f64>>,
) -> Result<Partner, InputError> {
    let n = p.len() as u32;
    for id in std::iter::once(particle).chain(partner) {
        if id >= n {
            return Err(InputError::new(
                format!("check[{k}].particle"),
                id,
                format!("must be a particle id in 0..{n}"),
            ));
        }
    }
    let mi = p.material[particle as usize] as usize;
    let (to, mj) = match (partner, wall) {
        (Some(j), None) if j != particle => (Partner::Particle(j), p.material[j as usize] as usize),
        (None, Some(w)) => {
            let names: Vec<&str> = setup.walls.iter().map(|x| x.name.as_str()).collect();
            let w = names.iter().position(|x| *x == w).ok_or_else(|| {
                InputError::new(
                    format!("check[{k}].wall"),
                    format!("\"{w}\""),
                    format!("must name a wall, one of {names:?}"),
                )
            })?;
            (
                Partner::Wall(w),
                setup.walls[w].material.map_or(mi, |m| m as usize),
            )
        }
        _ => {
            return Err(InputError::new(
                format!("check[{k}]"),
                format!("partner = {partner:?}, wall = {wall:?}"),
                "exactly one of partner (another particle) and wall",
            ))
        }
    };
    let hertz = setup
        .granular
        .as_ref()
        .is_some_and(|t| t.get(mi, mj).normal == Normal::HertzMaterial);
    let needs = match measure {
        Measure::MaxOverlap | Measure::PeakForce | Measure::ContactTime if !hertz => {
            Some("a hertz/material law for the pair (the values are Hertz's)")
        }
        Measure::Restitution if restitution.get(mi, mj).is_none() => {
            Some("a damping given by restitution (tsuji or restitution) for the pair")
        }
        Measure::TangentialVelocity | Measure::AngularVelocity
            if wall.is_none() || setup.granular.is_none() =>
        {
            Some("a wall and the granular law (the rigid-body limit of a body on a wall)")
        }
        _ => None,
    };
    match needs {
        Some(why) => Err(InputError::new(
            format!("check[{k}].measure"),
            format!("{measure:?}"),
            format!("needs {why}"),
        )),
        None => Ok(to),
    }
}
