//! Pouring (`[pour]`): spheres inserted during a run from a region at a rate (spheres/s
//! or kg/s) until a count or a mass, radii drawn as a fill's, with an initial velocity.
//!
//! After each step the pour inserts what the rate says is due. A sphere is placed at
//! random in the region, clear of every sphere there (those poured in the same step
//! too) and of every wall; a sphere that finds no room in [`TRIES`] places waits for a
//! later step (the pour falls behind and catches up when there is room). The k-th
//! poured sphere's radius and its places in step s come from random streams of (seed,
//! k) and (seed, s, k): what the pour does depends on the state alone, so a run resumed
//! from a checkpoint pours as the straight run does, bit for bit. It reads only the
//! spheres near its region ([`Pour::near`]) and the largest radius, which a run spread
//! over ranks gathers by id on every rank, so every rank draws the same spheres.

use super::assemble::{finite3, fits, material_index, region_box};
use super::scenario::{RegionSpec, Scenario};
use crate::dem::assemble::lattice_values;
use crate::dem::scenario::RadiusSpec;
use glam::DVec3;
use grains_core::input::{positive, InputError};
use grains_core::rng;
use grains_dem3d::{Particles, Setup, State};
use rand::RngExt;
use serde::{Deserialize, Serialize};

/// Random places tried for one sphere in one step before it waits for the next.
pub const TRIES: usize = 30;

/// `[pour]`: where, what, how fast and how much.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PourSpec {
    /// Material name.
    pub material: String,
    /// The region spheres are inserted in (wholly inside it).
    pub region: RegionSpec,
    /// Radius distribution (as a fill's).
    pub radius: RadiusSpec,
    /// Spheres per second (or `mass_rate`).
    #[serde(default)]
    pub rate: Option<f64>,
    /// Kilograms per second (or `rate`).
    #[serde(default)]
    pub mass_rate: Option<f64>,
    /// Stop after this many spheres.
    #[serde(default)]
    pub count: Option<u64>,
    /// Stop once this mass (kg) is poured (the last sphere may pass it).
    #[serde(default)]
    pub mass: Option<f64>,
    /// Initial velocity of every poured sphere (m/s).
    #[serde(default)]
    pub velocity: [f64; 3],
    /// Random seed.
    #[serde(default)]
    pub seed: u64,
}

/// How fast the pour goes.
#[derive(Clone, Copy, Debug)]
enum Rate {
    Spheres(f64),
    Kilograms(f64),
}

/// A validated pour and what it has poured.
#[derive(Clone, Debug)]
pub struct Pour {
    material: u16,
    density: f64,
    inertia_factor: f64,
    region: RegionSpec,
    lo: DVec3,
    hi: DVec3,
    radii: (f64, f64),
    rate: Rate,
    count: Option<u64>,
    mass: Option<f64>,
    velocity: DVec3,
    seed: u64,
    first_id: u32,
    inserted: u64,
    inserted_mass: f64,
}

impl Pour {
    /// Validates `[pour]` of `s`; poured spheres take ids from `first_id` on.
    pub fn new(s: &Scenario, spec: &PourSpec, first_id: u32) -> Result<Self, InputError> {
        let key = "pour";
        let material = material_index(s, "pour.material", &spec.material)?;
        let m = &s.materials[material as usize];
        let radii = lattice_values(key, &spec.radius, f64::NAN, 0.0)?;
        let (lo, hi) = region_box(key, &spec.region)?;
        let centre = 0.5 * (lo + hi);
        if !fits(&spec.region, centre, radii.1) {
            return Err(InputError::new(
                "pour.region",
                format!("{:?}", spec.region),
                format!("must hold a sphere of the largest radius, {}", radii.1),
            ));
        }
        for a in 0..3 {
            let (dl, dh) = (s.domain.lo[a], s.domain.hi[a]);
            if !s.domain.periodic[a] && (lo[a] < dl || hi[a] > dh) {
                return Err(InputError::new(
                    "pour.region",
                    format!("{:?}", spec.region),
                    format!(
                        "must lie inside the domain along {} ({dl} to {dh})",
                        super::assemble::AXES[a]
                    ),
                ));
            }
        }
        let rate = match (spec.rate, spec.mass_rate) {
            (Some(r), None) => {
                positive("pour.rate", r)?;
                Rate::Spheres(r)
            }
            (None, Some(r)) => {
                positive("pour.mass_rate", r)?;
                Rate::Kilograms(r)
            }
            (r, w) => {
                return Err(InputError::new(
                    "pour",
                    format!("rate = {r:?}, mass_rate = {w:?}"),
                    "exactly one of rate (spheres/s) and mass_rate (kg/s)",
                ))
            }
        };
        if spec.count.is_none() && spec.mass.is_none() {
            return Err(InputError::new(
                "pour",
                "neither count nor mass",
                "at least one of count (spheres) and mass (kg) to stop at",
            ));
        }
        if spec.count == Some(0) {
            return Err(InputError::new("pour.count", 0, "must be at least 1"));
        }
        if let Some(w) = spec.mass {
            positive("pour.mass", w)?;
        }
        Ok(Pour {
            material,
            density: m.density,
            inertia_factor: m.inertia_factor,
            region: spec.region,
            lo,
            hi,
            radii,
            rate,
            count: spec.count,
            mass: spec.mass,
            velocity: finite3("pour.velocity", spec.velocity)?,
            seed: spec.seed,
            first_id,
            inserted: 0,
            inserted_mass: 0.0,
        })
    }

    /// Its smallest and largest spheres, at the region's centre (for the time step, the
    /// neighbour skin and the periodic lengths).
    pub fn samples(&self) -> Particles {
        let mut p = Particles::default();
        for r in [self.radii.0, self.radii.1] {
            p.push(
                0.5 * (self.lo + self.hi),
                r,
                self.density,
                self.inertia_factor,
                self.material,
                DVec3::ZERO,
                DVec3::ZERO,
            );
        }
        p
    }

    /// What of it `state` holds (every sphere with an id from the first poured one on),
    /// summed in id order as the pour summed it.
    pub fn resumed(mut self, state: &State) -> Self {
        let p = &state.particles;
        let mut poured: Vec<(u32, f64)> = (0..p.len())
            .filter(|&i| p.id[i] >= self.first_id)
            .map(|i| (p.id[i], p.mass(i)))
            .collect();
        poured.sort_unstable_by_key(|x| x.0);
        self.inserted = poured.len() as u64;
        self.inserted_mass = poured.iter().fold(0.0, |m, x| m + x.1);
        self
    }

    /// Spheres the pour will have poured when it stops (by its mass, at the mean
    /// radius's mass, when it stops at a mass first).
    pub fn planned(&self) -> u64 {
        let r = 0.5 * (self.radii.0 + self.radii.1);
        let by_mass = self
            .mass
            .map(|m| (m / grains_dem3d::math::mass(self.density, r)).ceil() as u64);
        match (self.count, by_mass) {
            (Some(n), Some(k)) => n.min(k),
            (n, k) => n.or(k).unwrap_or(0),
        }
    }

    /// Spheres poured so far.
    pub fn inserted(&self) -> u64 {
        self.inserted
    }

    /// Mass poured so far (kg).
    pub fn inserted_mass(&self) -> f64 {
        self.inserted_mass
    }

    /// Whether the pour has reached its count or mass.
    pub fn done(&self) -> bool {
        self.count.is_some_and(|n| self.inserted >= n)
            || self.mass.is_some_and(|m| self.inserted_mass >= m)
    }

    /// Whether the rate has more due at time `t` than is poured.
    fn behind(&self, t: f64) -> bool {
        match self.rate {
            Rate::Spheres(r) => (self.inserted as f64) < (r * t).floor(),
            Rate::Kilograms(w) => self.inserted_mass < w * t,
        }
    }

    fn radius(&self, k: u64) -> f64 {
        let (lo, hi) = self.radii;
        if hi > lo {
            rng::stream(self.seed, k).random_range(lo..hi)
        } else {
            lo
        }
    }

    /// Its largest radius.
    pub fn largest(&self) -> f64 {
        self.radii.1
    }

    /// Whether spheres are due after the step that ended at `time`.
    pub fn due(&self, time: f64) -> bool {
        !self.done() && self.behind(time)
    }

    /// Whether a sphere at `at` of radius `r` may stand in a new sphere's way, with
    /// `r_max` the largest radius of the run's spheres.
    pub fn near(&self, setup: &Setup, (at, r): (DVec3, f64), r_max: f64) -> bool {
        let centre = 0.5 * (self.lo + self.hi);
        let reach = 0.5 * (self.hi - self.lo) + self.radii.1 + r_max;
        (setup.domain.min_image(at - centre).abs() - r)
            .cmple(reach)
            .all()
    }

    /// The spheres due after the step `step` that ended at `time` ([`Pour::due`]), each
    /// placed clear of the spheres `near` ([`Pour::near`]), of those placed before it and
    /// of every wall, in the order their ids follow; counted as poured.
    pub fn draw(&mut self, setup: &Setup, near: &Particles, (step, time): (u64, f64)) -> Particles {
        let d = &setup.domain;
        let mut near: Vec<(DVec3, f64)> = near
            .pos
            .iter()
            .copied()
            .zip(near.radius.iter().copied())
            .collect();
        let mut batch = Particles::default();
        let place = self.seed.wrapping_add(1).wrapping_add(step);
        while self.due(time) {
            let r = self.radius(self.inserted);
            let mut rng = rng::stream(place, self.inserted);
            let clear = |at: DVec3| {
                fits(&self.region, at, r)
                    && near
                        .iter()
                        .all(|&(q, rq)| d.min_image(at - q).length() >= r + rq)
                    && setup
                        .walls
                        .iter()
                        .all(|w| w.shape.nearest(at).is_none_or(|t| t.distance >= r))
            };
            let found = (0..TRIES)
                .map(|_| {
                    self.lo
                        + DVec3::new(rng.random(), rng.random(), rng.random()) * (self.hi - self.lo)
                })
                .find(|&at| clear(at));
            let Some(at) = found else {
                break;
            };
            batch.push(
                at,
                r,
                self.density,
                self.inertia_factor,
                self.material,
                self.velocity,
                DVec3::ZERO,
            );
            near.push((at, r));
            self.inserted += 1;
            self.inserted_mass += batch.mass(batch.len() - 1);
        }
        batch
    }
}
