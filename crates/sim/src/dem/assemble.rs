//! Turns a parsed scenario into the engine's inputs, validating every value on the way.
//! Nothing here writes to disk: a scenario that fails leaves no output behind.

use super::scenario::{CheckSpec, FigureSpec, ParticleSource, RadiusSpec, Scenario};
use glam::DVec2;
use grains_core::input::{named_list, positive, time_step, InputError, Shown};
use grains_core::rng;
use grains_dem::{timestep, Domain, PairTable, Particles, Setup, Wall};
use rand::RngExt;
use std::path::Path;

/// A scenario ready to run.
pub struct Assembled {
    /// Engine configuration.
    pub setup: Setup,
    /// Initial particles (creation order = id).
    pub particles: Particles,
    /// Time step (s).
    pub dt: f64,
    /// Largest stable time step (s).
    pub dt_critical: f64,
    /// Steps to run (at most, if the run stops at rest).
    pub steps: u64,
}

/// Validates and assembles. `base` is the directory relative paths are read from.
pub fn assemble(s: &Scenario, base: &Path) -> Result<Assembled, InputError> {
    assemble_with(s, base, None)
}

/// The index of material `name`, referred to at `key`.
fn material_index(s: &Scenario, key: &str, name: &str) -> Result<u16, InputError> {
    s.materials
        .iter()
        .position(|m| m.name == name)
        .map(|k| k as u16)
        .ok_or_else(|| {
            let names: Vec<&str> = s.materials.iter().map(|m| m.name.as_str()).collect();
            InputError::new(
                key,
                format!("\"{name}\""),
                format!("must be one of {names:?}"),
            )
        })
}

/// The particles of the scenario's `[[particles]]` groups, in creation order (= id).
pub fn particles(s: &Scenario, base: &Path) -> Result<Particles, InputError> {
    let material_index = |key: &str, name: &str| material_index(s, key, name);
    let mut particles = Particles::default();
    for (g, src) in s.particles.iter().enumerate() {
        add_group(s, g, src, base, &material_index, &mut particles)?;
    }
    Ok(particles)
}

/// Like [`assemble`], but with the particles given (those of a checkpoint) instead of
/// built from the scenario's sources.
pub fn assemble_with(
    s: &Scenario,
    base: &Path,
    given: Option<Particles>,
) -> Result<Assembled, InputError> {
    let domain = domain_of(s);
    for (k, (a, b)) in ["x", "y"].iter().zip(s.domain.lo.iter().zip(&s.domain.hi)) {
        if !(a.is_finite() && b.is_finite() && b > a) {
            return Err(InputError::new(
                format!("domain.hi.{k}"),
                b,
                format!("must be finite and greater than domain.lo.{k} = {a}"),
            ));
        }
    }
    named_list("material", s.materials.iter().map(|m| m.name.as_str()))?;
    for (k, g) in s.gravity.iter().enumerate() {
        if !g.is_finite() {
            return Err(InputError::new(
                format!("gravity[{k}]"),
                g,
                "must be finite",
            ));
        }
    }

    let particles = match given {
        None => particles(s, base)?,
        Some(p) => p,
    };
    if let Some(&m) = particles
        .material
        .iter()
        .find(|&&m| m as usize >= s.materials.len())
    {
        return Err(InputError::new(
            "material",
            m as u64,
            format!(
                "the checkpoint names material {m}, the scenario has {}",
                s.materials.len()
            ),
        ));
    }
    if particles.is_empty() {
        return Err(InputError::new(
            "particles",
            "(none)",
            "at least one particle is required",
        ));
    }

    let mut walls = Vec::new();
    for (w, spec) in s.walls.iter().enumerate() {
        let key = format!("wall[{w}]");
        let shape = spec.shape();
        match shape {
            grains_dem::WallShape::Segment { a, b } => {
                if a == b || !a.iter().chain(&b).all(|v| v.is_finite()) {
                    return Err(InputError::new(
                        format!("{key}.b"),
                        format!("{b:?}"),
                        "must be finite and differ from a",
                    ));
                }
            }
            grains_dem::WallShape::Circle { radius, centre, .. } => {
                positive(&format!("{key}.radius"), radius)?;
                if !centre.iter().all(|v| v.is_finite()) {
                    return Err(InputError::new(
                        format!("{key}.centre"),
                        format!("{centre:?}"),
                        "must be finite",
                    ));
                }
            }
        }
        if s.walls[..w].iter().any(|o| o.name() == spec.name()) {
            return Err(InputError::new(
                format!("{key}.name"),
                format!("\"{}\"", spec.name()),
                "wall names must be unique",
            ));
        }
        let material = match spec.material() {
            Some(name) => Some(material_index(s, &format!("{key}.material"), name)?),
            None => None,
        };
        walls.push(Wall {
            name: spec.name().to_string(),
            shape,
            material,
            motion: Default::default(),
        });
    }

    let mean_d = 2.0 * particles.radius.iter().sum::<f64>() / particles.len() as f64;
    let skin = s.run.validate(mean_d)?;
    s.output.validate(&super::CAPABILITIES, s.run.duration)?;
    if let Some(d) = &s.dispersal {
        if d.centre.is_none() {
            return Err(InputError::new(
                "dispersal.centre",
                "(missing)",
                "required: the centre of the polar grid, [x, y] in m",
            ));
        }
        d.validate("dispersal", s.run.duration)?;
    }
    let laws = crate::law::dim2::resolve(&s.contact, &s.materials)?;
    let mut setup = Setup::new(
        domain,
        s.materials.clone(),
        laws.model,
        walls,
        DVec2::from(s.gravity),
        skin,
    )?;
    setup.granular = laws.granular;
    let dt_critical = timestep::critical_dt(&setup, &particles);
    let dt = time_step(
        s.run.dt,
        s.run.safety,
        dt_critical,
        "Rayleigh time or stiffest contact, lightest particle",
    )?;

    check_inside(&setup, &particles)?;
    check_periodic(&setup, &particles)?;
    check_wall_overlaps(&setup, &particles)?;
    check_references(s, &setup, &particles, &laws.restitution)?;
    let steps = (s.run.duration / dt).ceil() as u64;
    Ok(Assembled {
        setup,
        particles,
        dt,
        dt_critical,
        steps,
    })
}

/// Every particle must start inside the domain along its non-periodic axes (along a
/// periodic one it is folded in).
fn check_inside(setup: &Setup, p: &Particles) -> Result<(), InputError> {
    let d = &setup.domain;
    for i in 0..p.len() {
        let x = p.pos[i];
        for (a, axis) in ["x", "y"].iter().enumerate() {
            let inside = x[a] >= d.lo[a] && x[a] <= d.hi[a];
            if !d.periodic[a] && !inside {
                return Err(InputError::new(
                    format!("particle {} at ({}, {})", p.id[i], x.x.shown(), x.y.shown()),
                    format!("{axis} = {}", x[a].shown()),
                    format!(
                        "must lie inside the domain: domain.lo.{axis} = {} to domain.hi.{axis} = {}",
                        d.lo[a].shown(),
                        d.hi[a].shown()
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The scenario's box as the engine sees it.
fn domain_of(s: &Scenario) -> Domain {
    Domain {
        lo: DVec2::from(s.domain.lo),
        hi: DVec2::from(s.domain.hi),
        periodic: s.domain.periodic,
    }
}

fn add_group(
    s: &Scenario,
    g: usize,
    src: &ParticleSource,
    base: &Path,
    material_index: &dyn Fn(&str, &str) -> Result<u16, InputError>,
    out: &mut Particles,
) -> Result<(), InputError> {
    let key = format!("particles[{g}]");
    let mut push =
        |mat: u16, at: DVec2, r: f64, v: DVec2, w: f64, what: &str| -> Result<(), InputError> {
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
        ParticleSource::List { material, disks } => {
            let mat = material_index(&format!("{key}.material"), material)?;
            for (k, d) in disks.iter().enumerate() {
                push(
                    mat,
                    DVec2::from(d.at),
                    d.radius,
                    DVec2::from(d.velocity),
                    d.omega,
                    &format!("disks[{k}]"),
                )?;
            }
        }
        ParticleSource::Lattice {
            material,
            region,
            count,
            radius,
            spacing,
            speed,
            seed,
        } => {
            let mat = material_index(&format!("{key}.material"), material)?;
            let (rmin, rmax) = lattice_values(&key, radius, *spacing, *speed)?;
            let pitch = 2.0 * rmax * spacing;
            let lo = DVec2::from(region.lo);
            let size = DVec2::from(region.hi) - lo;
            let nx = ((size.x - 2.0 * rmax) / pitch).floor() as i64 + 1;
            let ny = ((size.y - 2.0 * rmax) / pitch).floor() as i64 + 1;
            let capacity = if nx > 0 && ny > 0 {
                (nx * ny) as usize
            } else {
                0
            };
            if *count == 0 || *count > capacity {
                return Err(InputError::new(
                    format!("{key}.count"),
                    count,
                    format!("must be in 1..={capacity} (what the region holds at this spacing)"),
                ));
            }
            let mut rng = rng::seeded(*seed);
            for k in 0..*count {
                let (ix, iy) = ((k as i64 % nx) as f64, (k as i64 / nx) as f64);
                let at = lo + DVec2::splat(rmax) + DVec2::new(ix, iy) * pitch;
                let r = if rmax > rmin {
                    rng.random_range(rmin..rmax)
                } else {
                    rmin
                };
                let v = if *speed > 0.0 {
                    let a = rng.random_range(0.0..std::f64::consts::TAU);
                    *speed * rng.random::<f64>() * DVec2::new(a.cos(), a.sin())
                } else {
                    DVec2::ZERO
                };
                push(mat, at, r, v, 0.0, &format!("disk {k}"))?;
            }
        }
        ParticleSource::LammpsData {
            material,
            path,
            velocities,
        } => {
            let mat = material_index(&format!("{key}.material"), material)?;
            let full = base.join(path);
            let data = grains_core::lammps_data::read(&full).map_err(|e| {
                InputError::new(
                    format!("{key}.path"),
                    format!("\"{}\"", full.display()),
                    format!("must be a LAMMPS atom_style sphere data file: {e}"),
                )
            })?;
            data.require_dimension(2, &full.display().to_string())
                .map_err(|e| {
                    InputError::new(format!("{key}.path"), format!("\"{}\"", full.display()), e)
                })?;
            // The reader unwraps atoms by their image flags; put them back in the box, as
            // LAMMPS keeps them and `grains bench dem --lammps-data` reads them, so that
            // both start from the same bits.
            let domain = domain_of(s);
            for a in &data.atoms {
                let (v, w) = if *velocities {
                    (DVec2::new(a.vel[0], a.vel[1]), a.omega[2])
                } else {
                    (DVec2::ZERO, 0.0)
                };
                push(
                    mat,
                    domain.wrap(DVec2::new(a.pos[0], a.pos[1])),
                    0.5 * a.diameter,
                    v,
                    w,
                    &format!("atom {}", a.id),
                )?;
            }
        }
        ParticleSource::File { material, path } => {
            let mat = material_index(&format!("{key}.material"), material)?;
            let full = base.join(path);
            let text = std::fs::read_to_string(&full).map_err(|e| {
                InputError::new(
                    format!("{key}.path"),
                    format!("\"{}\"", full.display()),
                    format!("cannot be read: {e}"),
                )
            })?;
            for (ln, line) in text.lines().enumerate() {
                let line = line.trim();
                if line.is_empty() || line.starts_with('#') {
                    continue;
                }
                let v: Vec<f64> = line
                    .split_whitespace()
                    .map(str::parse)
                    .collect::<Result<_, _>>()
                    .map_err(|_| {
                        InputError::new(
                            format!("{key}.path"),
                            format!("\"{}\" line {}", full.display(), ln + 1),
                            "each line must hold three numbers: x y r",
                        )
                    })?;
                if v.len() != 3 {
                    return Err(InputError::new(
                        format!("{key}.path"),
                        format!("\"{}\" line {}", full.display(), ln + 1),
                        "each line must hold three numbers: x y r",
                    ));
                }
                push(
                    mat,
                    DVec2::new(v[0], v[1]),
                    v[2],
                    DVec2::ZERO,
                    0.0,
                    &format!("line {}", ln + 1),
                )?;
            }
        }
    }
    Ok(())
}

fn check_periodic(setup: &Setup, p: &Particles) -> Result<(), InputError> {
    let cut = 2.0 * p.max_radius() + setup.skin;
    let len = setup.domain.length();
    for (a, k) in ["x", "y"].iter().enumerate() {
        if setup.domain.periodic[a] && len[a] < 2.0 * cut {
            return Err(InputError::new(
                format!("domain.hi.{k}"),
                setup.domain.hi[a],
                format!(
                    "a periodic length must be at least 2 × (largest diameter + skin) = {:.4e} m",
                    2.0 * cut
                ),
            ));
        }
    }
    Ok(())
}

fn check_wall_overlaps(setup: &Setup, p: &Particles) -> Result<(), InputError> {
    for i in 0..p.len() {
        for (w, wall) in setup.walls.iter().enumerate() {
            if let Some(overlap) = grains_dem::diagnostics::wall_overlap(setup, p, i, w) {
                if overlap > super::RUNAWAY_OVERLAP * p.radius[i] {
                    return Err(InputError::new(
                        format!(
                            "particle {} at ({:.6e}, {:.6e})",
                            p.id[i], p.pos[i].x, p.pos[i].y
                        ),
                        format!("overlap {overlap:.4e} m with wall \"{}\"", wall.name),
                        format!(
                            "a particle may overlap a wall by at most {} of its radius ({:.4e} m; the run's runaway limit): move it off the wall",
                            super::RUNAWAY_OVERLAP,
                            super::RUNAWAY_OVERLAP * p.radius[i]
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

fn check_references(
    s: &Scenario,
    setup: &Setup,
    p: &Particles,
    restitution: &PairTable<Option<f64>>,
) -> Result<(), InputError> {
    let n = p.len() as u32;
    let wall = |k: usize, name: &str| -> Result<(), InputError> {
        if setup.walls.iter().any(|w| w.name == name) {
            Ok(())
        } else {
            let names: Vec<&str> = setup.walls.iter().map(|w| w.name.as_str()).collect();
            Err(InputError::new(
                format!("check[{k}].wall"),
                format!("\"{name}\""),
                format!("must name a wall, one of {names:?}"),
            ))
        }
    };
    let particle = |k: usize, id: u32| -> Result<(), InputError> {
        if id < n {
            Ok(())
        } else {
            Err(InputError::new(
                format!("check[{k}].particles"),
                id,
                format!("must be a particle id in 0..{n}"),
            ))
        }
    };
    for (k, c) in s.checks.iter().enumerate() {
        let tol = c.tolerance();
        if !(tol.is_finite() && tol > 0.0) {
            return Err(InputError::new(
                format!("check[{k}].tolerance"),
                tol,
                "must be a finite number > 0",
            ));
        }
        let linear_only = !matches!(
            c,
            CheckSpec::WallForceOverWeight { .. } | CheckSpec::Collision { .. }
        );
        if linear_only && setup.granular.is_some() {
            // Their analytic values are the linear spring-dashpot's (π/ω_d, the pair's e).
            return Err(InputError::new(
                format!("check[{k}]"),
                format!("\"{}\"", c.name()),
                "only under the linear law (contact.model \"material\" or \"hooke_history\"); its value is the linear spring's",
            ));
        }
        match c {
            CheckSpec::Restitution { particles, .. } | CheckSpec::ContactTime { particles, .. } => {
                particle(k, particles[0])?;
                particle(k, particles[1])?;
                if particles[0] == particles[1] {
                    return Err(InputError::new(
                        format!("check[{k}].particles"),
                        format!("{particles:?}"),
                        "must name two different particles",
                    ));
                }
            }
            CheckSpec::ImpactTangentialVelocity {
                particle: id,
                wall: w,
                ..
            }
            | CheckSpec::ImpactAngularVelocity {
                particle: id,
                wall: w,
                ..
            } => {
                particle(k, *id)?;
                wall(k, w)?;
            }
            CheckSpec::Collision {
                measure,
                particle,
                partner,
                wall,
                ..
            } => {
                crate::collision::dim2::validate(
                    k,
                    *measure,
                    *particle,
                    *partner,
                    wall.as_deref(),
                    setup,
                    p,
                    restitution,
                )?;
            }
            CheckSpec::WallForceOverWeight { wall: w, .. } => {
                wall(k, w)?;
                if setup.gravity == DVec2::ZERO {
                    return Err(InputError::new(
                        "gravity",
                        "[0, 0]",
                        format!("check[{k}] needs non-zero gravity"),
                    ));
                }
            }
        }
    }
    for (k, f) in s.figures.iter().enumerate() {
        if let FigureSpec::PackingFraction { margin, .. } = f {
            if !(margin.is_finite() && *margin >= 0.0) {
                return Err(InputError::new(
                    format!("figure[{k}].margin"),
                    margin,
                    "must be >= 0",
                ));
            }
        }
    }
    Ok(())
}

/// Checks one particle's radius and that its position and velocities are finite
/// (`finite`; `at` is shown when not): 2D and 3D alike.
pub fn sphere_values(
    key: &str,
    what: &str,
    r: f64,
    finite: bool,
    at: impl std::fmt::Debug,
) -> Result<(), InputError> {
    positive(&format!("{key}.{what}.radius"), r)?;
    if !finite {
        return Err(InputError::new(
            format!("{key}.{what}"),
            format!("{at:?}"),
            "position and velocity must be finite",
        ));
    }
    Ok(())
}

/// The radius range of a lattice or random group, its spacing (≥ 1) and initial speed
/// (≥ 0) checked: 2D and 3D alike. `spacing` NaN: not a lattice, not checked.
pub fn lattice_values(
    key: &str,
    radius: &RadiusSpec,
    spacing: f64,
    speed: f64,
) -> Result<(f64, f64), InputError> {
    let (rmin, rmax) = match *radius {
        RadiusSpec::Constant { value } => (value, value),
        RadiusSpec::Uniform { min, max } => (min, max),
    };
    positive(&format!("{key}.radius.min"), rmin)?;
    if !(rmax.is_finite() && rmax >= rmin) {
        return Err(InputError::new(
            format!("{key}.radius.max"),
            rmax,
            format!("must be >= radius.min = {rmin}"),
        ));
    }
    if !(spacing.is_nan() || spacing.is_finite() && spacing >= 1.0) {
        return Err(InputError::new(
            format!("{key}.spacing"),
            spacing,
            "must be >= 1 (particles would overlap)",
        ));
    }
    if !(speed.is_finite() && speed >= 0.0) {
        return Err(InputError::new(
            format!("{key}.speed"),
            speed,
            "must be >= 0",
        ));
    }
    Ok((rmin, rmax))
}
