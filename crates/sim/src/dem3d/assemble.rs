//! A 3D scenario validated and assembled into the engine's set-up; nothing is written,
//! so a scenario that fails leaves no output behind.

use super::pour::Pour;
use super::scenario::{CheckSpec, RegionSpec, Scenario, SphereSource};
use crate::dem::assemble::{lattice_values, sphere_values};
use crate::law::dim3::resolve;
use glam::DVec3;
use grains_core::input::{named_list, positive, time_step, InputError, Shown};
use grains_core::rng;
use grains_dem3d::{timestep, Domain, PairTable, Particles, Setup};
use rand::RngExt;
use std::collections::HashMap;

/// A 3D scenario ready to run.
pub struct Assembled {
    /// Engine configuration.
    pub setup: Setup,
    /// Initial spheres (creation order = id).
    pub particles: Particles,
    /// Time step (s).
    pub dt: f64,
    /// Largest stable time step (s).
    pub dt_critical: f64,
    /// Steps to run (at most).
    pub steps: u64,
    /// The restitution each pair's law is built for, where it takes one.
    pub restitution: PairTable<Option<f64>>,
    /// Spheres poured in during the run.
    pub pour: Option<Pour>,
}

pub(super) const AXES: [&str; 3] = ["x", "y", "z"];

pub(super) fn finite3(key: &str, v: [f64; 3]) -> Result<DVec3, InputError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(DVec3::from(v))
    } else {
        Err(InputError::new(
            key,
            format!("{v:?}"),
            "three finite numbers",
        ))
    }
}

/// The index of material `name`, referred to at `key`.
pub(super) fn material_index(s: &Scenario, key: &str, name: &str) -> Result<u16, InputError> {
    let names: Vec<&str> = s.materials.iter().map(|m| m.name.as_str()).collect();
    names
        .iter()
        .position(|m| *m == name)
        .map(|k| k as u16)
        .ok_or_else(|| {
            InputError::new(
                key,
                format!("\"{name}\""),
                format!("must be one of {names:?}"),
            )
        })
}

/// Validates and assembles `s`, whose relative paths start at `base`.
pub fn assemble(s: &Scenario, base: &std::path::Path) -> Result<Assembled, InputError> {
    if s.dim != 3 {
        return Err(InputError::new("dim", s.dim, "2 or 3"));
    }
    let lo = finite3("domain.lo", s.domain.lo)?;
    let hi = finite3("domain.hi", s.domain.hi)?;
    for a in 0..3 {
        if hi[a] <= lo[a] {
            return Err(InputError::new(
                format!("domain.hi.{}", AXES[a]),
                hi[a],
                format!(
                    "must be greater than domain.lo.{} = {}",
                    AXES[a],
                    lo[a].shown()
                ),
            ));
        }
    }
    let domain = Domain {
        lo,
        hi,
        periodic: s.domain.periodic,
    };
    let gravity = finite3("gravity", s.gravity)?;
    named_list("material", s.materials.iter().map(|m| m.name.as_str()))?;
    let laws = resolve(&s.contact, &s.materials)?;
    let mut particles = Particles::default();
    for (g, src) in s.particles.iter().enumerate() {
        add_group(s, base, g, src, &mut particles)?;
    }
    let pour = match &s.pour {
        Some(spec) => Some(Pour::new(s, spec, particles.len() as u32)?),
        None => None,
    };
    if pour.is_some() && s.run.stop_kinetic_ratio.is_some() {
        return Err(InputError::new(
            "run.stop_kinetic_ratio",
            s.run.stop_kinetic_ratio.unwrap_or_default(),
            "not with a [pour] (the weight it measures rest against grows while pouring); give run.duration alone",
        ));
    }
    if particles.is_empty() && pour.is_none() {
        return Err(InputError::new(
            "particles",
            "(none)",
            "at least one sphere (or a [pour]) is required",
        ));
    }
    // The poured spheres size the time step, the skin and the periodic lengths too.
    let sizing = match &pour {
        Some(p) => {
            let mut all = particles.clone();
            let extra = p.samples();
            for i in 0..extra.len() {
                let m = &s.materials[extra.material[i] as usize];
                all.push(
                    extra.pos[i],
                    extra.radius[i],
                    m.density,
                    m.inertia_factor,
                    extra.material[i],
                    DVec3::ZERO,
                    DVec3::ZERO,
                );
            }
            std::borrow::Cow::Owned(all)
        }
        None => std::borrow::Cow::Borrowed(&particles),
    };
    let walls = super::walls::walls(s)?;
    let mean_d = 2.0 * sizing.radius.iter().sum::<f64>() / sizing.len() as f64;
    let skin = s.run.validate(mean_d)?;
    s.output.validate(&super::CAPABILITIES, s.run.duration)?;
    let mut setup = Setup::new(
        domain,
        s.materials.clone(),
        laws.model,
        walls,
        gravity,
        skin,
    )?;
    setup.granular = laws.granular;
    // The law bounds the step (`ContactLaw::stable_step`): Hertz by the Rayleigh time.
    let dt_critical = timestep::critical_dt(&setup, &sizing);
    let dt = time_step(
        s.run.dt,
        s.run.safety,
        dt_critical,
        "Rayleigh time or stiffest contact, smallest sphere",
    )?;
    starts_inside(&setup, &sizing)?;
    walls_clear(&setup, &particles)?;
    checks(s, &setup, &particles, &laws.restitution)?;
    let steps = (s.run.duration / dt).ceil() as u64;
    Ok(Assembled {
        setup,
        particles,
        dt,
        dt_critical,
        steps,
        restitution: laws.restitution,
        pour,
    })
}

/// The box about `region`, its values checked.
pub(super) fn region_box(key: &str, region: &RegionSpec) -> Result<(DVec3, DVec3), InputError> {
    match *region {
        RegionSpec::Box { lo, hi } => {
            let (l, h) = (
                finite3(&format!("{key}.region.lo"), lo)?,
                finite3(&format!("{key}.region.hi"), hi)?,
            );
            if !l.cmplt(h).all() {
                return Err(InputError::new(
                    format!("{key}.region.hi"),
                    format!("{hi:?}"),
                    format!("must exceed region.lo = {lo:?} on every axis"),
                ));
            }
            Ok((l, h))
        }
        RegionSpec::Cylinder {
            base,
            radius,
            height,
        } => {
            let b = finite3(&format!("{key}.region.base"), base)?;
            positive(&format!("{key}.region.radius"), radius)?;
            positive(&format!("{key}.region.height"), height)?;
            Ok((
                b - DVec3::new(radius, radius, 0.0),
                b + DVec3::new(radius, radius, height),
            ))
        }
    }
}

/// Whether a sphere of radius `r` at `p` lies inside `region`.
pub(super) fn fits(region: &RegionSpec, p: DVec3, r: f64) -> bool {
    match *region {
        RegionSpec::Box { lo, hi } => {
            (p - r).cmpge(DVec3::from(lo)).all() && (p + r).cmple(DVec3::from(hi)).all()
        }
        RegionSpec::Cylinder {
            base,
            radius,
            height,
        } => {
            let d = p - DVec3::from(base);
            d.z >= r && d.z <= height - r && d.truncate().length() <= radius - r
        }
    }
}

fn add_group(
    s: &Scenario,
    base: &std::path::Path,
    g: usize,
    src: &SphereSource,
    out: &mut Particles,
) -> Result<(), InputError> {
    let key = format!("particles[{g}]");
    let mut push =
        |mat: u16, at: DVec3, r: f64, v: DVec3, w: DVec3, what: &str| -> Result<(), InputError> {
            sphere_values(
                &key,
                what,
                r,
                at.is_finite() && v.is_finite() && w.is_finite(),
                at,
            )?;
            let m = &s.materials[mat as usize];
            out.push(at, r, m.density, m.inertia_factor, mat, v, w);
            Ok(())
        };
    match src {
        SphereSource::List { material, spheres } => {
            let mat = material_index(s, &format!("{key}.material"), material)?;
            for (k, p) in spheres.iter().enumerate() {
                let what = format!("spheres[{k}]");
                push(
                    mat,
                    DVec3::from(p.at),
                    p.radius,
                    DVec3::from(p.velocity),
                    DVec3::from(p.omega),
                    &what,
                )?;
            }
        }
        SphereSource::Lattice {
            material,
            region,
            count,
            radius,
            spacing,
            speed,
            seed,
        } => {
            let mat = material_index(s, &format!("{key}.material"), material)?;
            let (rmin, rmax) = lattice_values(&key, radius, *spacing, *speed)?;
            let (lo, hi) = region_box(&key, region)?;
            let pitch = 2.0 * rmax * spacing;
            let n = ((hi - lo - 2.0 * rmax) / pitch).floor() + 1.0;
            let cells = n.max(DVec3::ZERO);
            // Layer by layer from the bottom, each layer row by row.
            let mut sites = Vec::new();
            'fill: for iz in 0..cells.z as u64 {
                for iy in 0..cells.y as u64 {
                    for ix in 0..cells.x as u64 {
                        let at = lo + rmax + DVec3::new(ix as f64, iy as f64, iz as f64) * pitch;
                        if fits(region, at, rmax) {
                            sites.push(at);
                            if sites.len() == *count {
                                break 'fill;
                            }
                        }
                    }
                }
            }
            if *count == 0 || sites.len() < *count {
                return Err(InputError::new(
                    format!("{key}.count"),
                    count,
                    format!(
                        "must be in 1..={} (what the region holds at this spacing)",
                        sites.len()
                    ),
                ));
            }
            let mut rng = rng::seeded(*seed);
            for (k, at) in sites.into_iter().enumerate() {
                let r = if rmax > rmin {
                    rng.random_range(rmin..rmax)
                } else {
                    rmin
                };
                let v = if *speed > 0.0 {
                    let u = DVec3::new(
                        rng.random::<f64>() - 0.5,
                        rng.random::<f64>() - 0.5,
                        rng.random::<f64>() - 0.5,
                    );
                    *speed * rng.random::<f64>() * u.normalize_or_zero()
                } else {
                    DVec3::ZERO
                };
                push(mat, at, r, v, DVec3::ZERO, &format!("sphere {k}"))?;
            }
        }
        SphereSource::File {
            material,
            path,
            offset,
        } => {
            let mat = material_index(s, &format!("{key}.material"), material)?;
            let shift = finite3(&format!("{key}.offset"), *offset)?;
            for (k, (at, r)) in super::packing::read(&key, &base.join(path))?
                .into_iter()
                .enumerate()
            {
                let what = format!("line {} of the file's spheres", k + 1);
                push(
                    mat,
                    DVec3::from(at) + shift,
                    r,
                    DVec3::ZERO,
                    DVec3::ZERO,
                    &what,
                )?;
            }
        }
        SphereSource::Random {
            material,
            region,
            count,
            radius,
            seed,
        } => {
            let mat = material_index(s, &format!("{key}.material"), material)?;
            let (rmin, rmax) = lattice_values(&key, radius, f64::NAN, 0.0)?;
            let (lo, hi) = region_box(&key, region)?;
            let mut rng = rng::seeded(*seed);
            // Placed spheres by grid cell of one largest diameter: a new one need only
            // look at the 27 cells about its own.
            let cell = 2.0 * rmax;
            let index = |p: DVec3| ((p - lo) / cell).floor().as_ivec3();
            let mut grid: HashMap<glam::IVec3, Vec<(DVec3, f64)>> = HashMap::new();
            let (mut placed, mut tries, mut misses) = (0usize, 0usize, 0usize);
            while placed < *count {
                tries += 1;
                misses += 1;
                // Room is found ever more rarely as the region fills: 10⁵ misses in a row
                // mean it is (nearly) full.
                if misses > 100_000 {
                    return Err(InputError::new(
                        format!("{key}.count"),
                        count,
                        format!("only {placed} spheres found room in the region after {tries} random tries (the last 100000 in vain); lower the count or enlarge the region"),
                    ));
                }
                let r = if rmax > rmin {
                    rng.random_range(rmin..rmax)
                } else {
                    rmin
                };
                let at = lo
                    + DVec3::new(
                        rng.random::<f64>(),
                        rng.random::<f64>(),
                        rng.random::<f64>(),
                    ) * (hi - lo);
                if !fits(region, at, r) {
                    continue;
                }
                let c = index(at);
                let clear = (-1..=1).all(|dx| {
                    (-1..=1).all(|dy| {
                        (-1..=1).all(|dz| {
                            grid.get(&(c + glam::IVec3::new(dx, dy, dz)))
                                .is_none_or(|v| v.iter().all(|(q, rq)| q.distance(at) >= r + rq))
                        })
                    })
                });
                if clear {
                    grid.entry(c).or_default().push((at, r));
                    push(
                        mat,
                        at,
                        r,
                        DVec3::ZERO,
                        DVec3::ZERO,
                        &format!("sphere {placed}"),
                    )?;
                    placed += 1;
                    misses = 0;
                }
            }
        }
    }
    Ok(())
}

/// Every sphere starts inside the domain along its non-periodic axes.
fn starts_inside(setup: &Setup, p: &Particles) -> Result<(), InputError> {
    let d = &setup.domain;
    for i in 0..p.len() {
        let x = p.pos[i];
        let outside = |a: usize| !(d.periodic[a] || x[a] >= d.lo[a] && x[a] <= d.hi[a]);
        if let Some(a) = (0..3).find(|&a| outside(a)) {
            return Err(InputError::new(
                format!("particle {} at {:?}", p.id[i], x.to_array()),
                format!("{} = {}", AXES[a], x[a].shown()),
                format!(
                    "must lie inside the domain, {} to {}",
                    d.lo[a].shown(),
                    d.hi[a].shown()
                ),
            ));
        }
    }
    let cut = 2.0 * (2.0 * p.max_radius() + setup.skin);
    for (a, axis) in AXES.iter().enumerate() {
        if d.periodic[a] && d.length()[a] < cut {
            return Err(InputError::new(
                format!("domain.hi.{axis}"),
                d.hi[a],
                format!("a periodic length must be at least 2 × (largest diameter + skin) = {cut:.4e} m"),
            ));
        }
    }
    Ok(())
}

/// No sphere starts deeper in a wall than the run's runaway limit.
fn walls_clear(setup: &Setup, p: &Particles) -> Result<(), InputError> {
    for i in 0..p.len() {
        for (w, wall) in setup.walls.iter().enumerate() {
            let Some(overlap) = grains_dem3d::diagnostics::wall_overlap(setup, p, i, w) else {
                continue;
            };
            let limit = crate::dem::RUNAWAY_OVERLAP * p.radius[i];
            if overlap > limit {
                return Err(InputError::new(
                    format!("particle {} at {:?}", p.id[i], p.pos[i].to_array()),
                    format!("overlap {overlap:.4e} m with wall \"{}\"", wall.name),
                    format!("at most {} of its radius ({limit:.4e} m; the run's runaway limit): move it off the wall", crate::dem::RUNAWAY_OVERLAP),
                ));
            }
        }
    }
    Ok(())
}

fn checks(
    s: &Scenario,
    setup: &Setup,
    p: &Particles,
    e: &PairTable<Option<f64>>,
) -> Result<(), InputError> {
    let n = p.len() as u32;
    let wall_index = |k: usize, name: &str| -> Result<usize, InputError> {
        let names: Vec<&str> = setup.walls.iter().map(|w| w.name.as_str()).collect();
        names.iter().position(|w| *w == name).ok_or_else(|| {
            InputError::new(
                format!("check[{k}].wall"),
                format!("\"{name}\""),
                format!("must name a wall, one of {names:?}"),
            )
        })
    };
    for (k, c) in s.checks.iter().enumerate() {
        if let Some(t) = c.tolerance() {
            positive(&format!("check[{k}].tolerance"), t)?;
        }
        match c {
            CheckSpec::Collision {
                measure,
                particle,
                partner,
                wall,
                ..
            } => {
                crate::collision::dim3::validate(
                    k,
                    *measure,
                    *particle,
                    *partner,
                    wall.as_deref(),
                    setup,
                    p,
                    e,
                )?;
            }
            CheckSpec::FinalVelocity {
                particle,
                direction,
                expected,
                ..
            } => {
                if *particle >= n {
                    return Err(InputError::new(
                        format!("check[{k}].particle"),
                        particle,
                        format!("must be a particle id in 0..{n}"),
                    ));
                }
                let d = finite3(&format!("check[{k}].direction"), *direction)?;
                if d == DVec3::ZERO {
                    return Err(InputError::new(
                        format!("check[{k}].direction"),
                        format!("{direction:?}"),
                        "must not be zero",
                    ));
                }
                if !expected.is_finite() || *expected == 0.0 {
                    return Err(InputError::new(
                        format!("check[{k}].expected"),
                        expected,
                        "must be a finite non-zero number (the check is relative)",
                    ));
                }
            }
            CheckSpec::ReposeAngle { wall, after, .. }
            | CheckSpec::DrumTorque { wall, after, .. } => {
                let w = wall_index(k, wall)?;
                if !matches!(
                    setup.walls[w].shape,
                    grains_dem3d::WallShape::Cylinder { .. }
                ) {
                    return Err(InputError::new(
                        format!("check[{k}].wall"),
                        format!("\"{wall}\""),
                        "must name a cylinder (the drum)",
                    ));
                }
                grains_core::input::non_negative(&format!("check[{k}].after"), *after)?;
                if let CheckSpec::ReposeAngle { lo, hi, .. } = c {
                    grains_core::input::in_range(&format!("check[{k}].lo"), *lo, 0.0, 90.0)?;
                    if !(hi.is_finite() && hi > lo && *hi <= 90.0) {
                        return Err(InputError::new(
                            format!("check[{k}].hi"),
                            hi,
                            format!("must exceed lo = {lo} and be at most 90 (degrees)"),
                        ));
                    }
                }
                if setup.gravity == DVec3::ZERO {
                    return Err(InputError::new(
                        "gravity",
                        "[0, 0, 0]",
                        format!("check[{k}] needs non-zero gravity"),
                    ));
                }
            }
            CheckSpec::EnergyClosure { max, .. } => {
                positive(&format!("check[{k}].max"), *max)?;
                if !s.analysis.energy_ledger {
                    return Err(InputError::new(
                        "analysis.energy_ledger",
                        "false",
                        format!("check[{k}] (energy_closure) needs the energy ledger on"),
                    ));
                }
            }
            CheckSpec::Beverloo {
                wall,
                after,
                packing,
                ..
            } => {
                let w = wall_index(k, wall)?;
                if !matches!(setup.walls[w].shape, grains_dem3d::WallShape::Disk { hole, .. } if hole > 0.0)
                {
                    return Err(InputError::new(
                        format!("check[{k}].wall"),
                        format!("\"{wall}\""),
                        "must name a disk with a hole (the silo's floor)",
                    ));
                }
                grains_core::input::non_negative(&format!("check[{k}].after"), *after)?;
                if !(*packing > 0.0 && *packing < 1.0) {
                    return Err(InputError::new(
                        format!("check[{k}].packing"),
                        packing,
                        "must lie in (0, 1)",
                    ));
                }
                if setup.gravity == DVec3::ZERO {
                    return Err(InputError::new(
                        "gravity",
                        "[0, 0, 0]",
                        format!("check[{k}] needs non-zero gravity"),
                    ));
                }
            }
            CheckSpec::PouredMass { region, .. } => {
                region_box(&format!("check[{k}]"), region)?;
                if s.pour.is_none() {
                    return Err(InputError::new(
                        format!("check[{k}].kind"),
                        "\"poured_mass\"",
                        "needs a [pour]",
                    ));
                }
            }
            CheckSpec::Runout { wall, .. } => {
                super::collapse::validate(k, s, setup, wall, wall_index(k, wall)?)?;
            }
            CheckSpec::WallForceOverWeight { wall, .. } => {
                wall_index(k, wall)?;
                if setup.gravity == DVec3::ZERO {
                    return Err(InputError::new(
                        "gravity",
                        "[0, 0, 0]",
                        format!("check[{k}] needs non-zero gravity"),
                    ));
                }
            }
        }
    }
    Ok(())
}
