//! Turns a parsed MPM scenario into the engine's inputs, validating every value on the
//! way. Nothing here writes to disk: a scenario that fails leaves no output behind.

use super::scenario::{CheckSpec, LawName, Scenario};
use glam::DVec2;
use grains_core::input::{named_list, positive, time_step, InputError, Shown};
use grains_mpm::{
    timestep, Body, ContactLaw, ContactTable, Grid, Motion, Particles, Setup, ShapeFunction,
    UpdateScheme,
};

/// A scenario ready to run.
pub struct Assembled {
    /// Engine configuration.
    pub setup: Setup,
    /// Initial points.
    pub particles: Particles,
    /// Exact area of each body's shape (m²).
    pub areas: Vec<f64>,
    /// Initial velocity of each body.
    pub velocities: Vec<DVec2>,
    /// Points per body.
    pub counts: Vec<usize>,
    /// Time step (s).
    pub dt: f64,
    /// Largest stable time step (s).
    pub dt_critical: f64,
    /// Steps to run.
    pub steps: u64,
}

fn law(key: &str, name: LawName, mu: Option<f64>) -> Result<ContactLaw, InputError> {
    match (name, mu) {
        (LawName::Coulomb, mu) => {
            let mu = mu.unwrap_or(0.0);
            if !(mu.is_finite() && mu >= 0.0) {
                return Err(InputError::new(
                    format!("{key}.mu"),
                    mu,
                    "must be a finite number >= 0",
                ));
            }
            Ok(ContactLaw::Coulomb { mu })
        }
        (LawName::NoSlip, None) => Ok(ContactLaw::NoSlip),
        (LawName::NoSlip, Some(mu)) => Err(InputError::new(
            format!("{key}.mu"),
            mu,
            "only a \"coulomb\" law takes a friction coefficient",
        )),
    }
}

/// Validates and assembles.
pub fn assemble(s: &Scenario) -> Result<Assembled, InputError> {
    if s.engine != "mpm" {
        return Err(InputError::new(
            "engine",
            format!("\"{}\"", s.engine),
            "must be \"mpm\" here",
        ));
    }
    let g = &s.grid;
    positive("grid.cell_size", g.cell_size)?;
    let mut cells = [0usize; 2];
    for (k, axis) in ["x", "y"].iter().enumerate() {
        let (a, b) = (g.lo[k], g.hi[k]);
        if !(a.is_finite() && b.is_finite() && b > a) {
            return Err(InputError::new(
                format!("grid.hi.{axis}"),
                b,
                format!("must be finite and greater than grid.lo.{axis} = {a}"),
            ));
        }
        let n = (b - a) / g.cell_size;
        if (n - n.round()).abs() > 1e-6 * n.max(1.0) || n.round() < 2.0 || n > 1e5 {
            return Err(InputError::new(
                "grid.cell_size",
                g.cell_size,
                format!(
                    "the domain's {axis} length {} must be a whole number (2 to 100000) of cells",
                    b - a
                ),
            ));
        }
        cells[k] = n.round() as usize;
    }
    if !(1..=8).contains(&g.particles_per_cell) {
        return Err(InputError::new(
            "grid.particles_per_cell",
            g.particles_per_cell,
            "must be 1 to 8 (points per cell along each axis)",
        ));
    }
    let grid = Grid {
        lo: DVec2::from(g.lo),
        h: g.cell_size,
        cells,
    };
    let shape = match s.method.shape.as_str() {
        "linear" => ShapeFunction::Linear,
        "gimp" => ShapeFunction::Gimp,
        "bspline2" => ShapeFunction::Bspline2,
        other => {
            return Err(InputError::new(
                "method.shape",
                format!("\"{other}\""),
                format!("unknown shape function; must be {}", ShapeFunction::NAMES),
            ))
        }
    };
    let scheme = match s.method.update.as_str() {
        "usf" => UpdateScheme::Usf,
        "usl" => UpdateScheme::Usl,
        "usavg" => UpdateScheme::Usavg,
        "musl" => UpdateScheme::Musl,
        other => {
            return Err(InputError::new(
                "method.update",
                format!("\"{other}\""),
                format!("unknown update scheme; must be {}", UpdateScheme::NAMES),
            ))
        }
    };
    named_list("material", s.materials.iter().map(|m| m.name()))?;
    for (k, m) in s.materials.iter().enumerate() {
        positive(&format!("material[{k}].density"), m.density())?;
        let (bulk, shear) = m.moduli();
        positive(&format!("material[{k}].bulk"), bulk)?;
        positive(&format!("material[{k}].shear"), shear)?;
    }
    if s.bodies.is_empty() {
        return Err(InputError::new(
            "body",
            "(none)",
            "at least one [[body]] is required",
        ));
    }
    let names: Vec<&str> = s.bodies.iter().map(|b| b.name.as_str()).collect();
    let body_index = |key: &str, name: &str| -> Result<usize, InputError> {
        names.iter().position(|n| *n == name).ok_or_else(|| {
            InputError::new(
                key,
                format!("\"{name}\""),
                format!("must be one of {names:?}"),
            )
        })
    };
    let pitch = g.cell_size / g.particles_per_cell as f64;
    let mut particles = Particles::default();
    let mut sites = std::collections::HashMap::new();
    let (mut bodies, mut areas, mut velocities, mut counts) = (vec![], vec![], vec![], vec![]);
    for (k, b) in s.bodies.iter().enumerate() {
        let key = format!("body[{k}]");
        if names[..k].contains(&b.name.as_str()) || b.name.is_empty() {
            return Err(InputError::new(
                format!("{key}.name"),
                format!("\"{}\"", b.name),
                "names must be unique and non-empty",
            ));
        }
        let material = s
            .materials
            .iter()
            .position(|m| m.name() == b.material)
            .ok_or_else(|| {
                let m: Vec<&str> = s.materials.iter().map(|m| m.name()).collect();
                InputError::new(
                    format!("{key}.material"),
                    format!("\"{}\"", b.material),
                    format!("must be one of {m:?}"),
                )
            })?;
        b.geometry.validate().map_err(|e| {
            InputError::new(format!("{key}.geometry"), e, "check the shape's parameters")
        })?;
        let v = DVec2::from(b.velocity);
        if !v.is_finite() {
            return Err(InputError::new(
                format!("{key}.velocity"),
                format!("{:?}", b.velocity),
                "must be finite",
            ));
        }
        let points = b.geometry.fill(grid.lo, pitch);
        if points.is_empty() {
            return Err(InputError::new(
                format!("{key}.geometry"),
                format!("{:?}", b.geometry),
                format!("holds no material point at this resolution (point pitch {pitch:e} m); enlarge the body or refine the grid"),
            ));
        }
        if let Some(x) = points.iter().find(|x| !grid.contains(**x)) {
            return Err(InputError::new(
                format!("{key}.geometry"),
                format!("point at ({:e}, {:e})", x.x, x.y),
                format!(
                    "every material point must lie inside the grid [{:?}, {:?}]",
                    g.lo, g.hi
                ),
            ));
        }
        // Every body is filled on the same lattice, so overlapping bodies put points on
        // the same lattice site. Rigid bodies moving together may overlap: they form
        // one rigid shape (a plate with half-cylinders fixed to it).
        for x in &points {
            let site = ((*x - grid.lo) / pitch).floor().as_i64vec2().to_array();
            if let Some(&other) = sites.get(&site) {
                let other: usize = other;
                let o = &s.bodies[other];
                let fused = b.rigid && o.rigid && o.velocity == b.velocity;
                if other != k && !fused {
                    return Err(InputError::new(
                        format!("{key}.geometry"),
                        format!("{:?}", b.geometry),
                        format!(
                            "overlaps body \"{}\" around ({}, {}); bodies may touch but not overlap (only rigid bodies moving together may)",
                            o.name,
                            x.x.shown(),
                            x.y.shown()
                        ),
                    ));
                }
            }
            sites.insert(site, k);
        }
        // Volumes are rescaled so the body has its exact area (a lattice count of a
        // curved shape is off by a few per cent at 8 cells per diameter).
        let area = b.geometry.area();
        let vol = area / points.len() as f64;
        let rho = s.materials[material].density();
        for x in &points {
            particles.push(k as u16, rho * vol, vol, *x, v);
        }
        bodies.push(Body {
            name: b.name.clone(),
            material,
            motion: if b.rigid {
                Motion::Prescribed(v)
            } else {
                Motion::Free
            },
            temperature: None,
        });
        areas.push(area);
        velocities.push(v);
        counts.push(points.len());
    }
    if s.bodies.len() > u16::MAX as usize {
        return Err(InputError::new(
            "body",
            s.bodies.len(),
            "at most 65535 bodies",
        ));
    }
    let mut contact =
        ContactTable::new(s.bodies.len(), law("contact", s.contact.law, s.contact.mu)?);
    for (k, p) in s.contact.pair.iter().enumerate() {
        let key = format!("contact.pair[{k}]");
        let a = body_index(&format!("{key}.bodies"), &p.bodies[0])?;
        let b = body_index(&format!("{key}.bodies"), &p.bodies[1])?;
        if a == b {
            return Err(InputError::new(
                format!("{key}.bodies"),
                format!("{:?}", p.bodies),
                "must name two different bodies",
            ));
        }
        contact.set(a, b, law(&key, p.law, p.mu)?);
    }
    if contact.distinct() > 255 {
        return Err(InputError::new(
            "contact.pair",
            s.contact.pair.len(),
            "at most 255 distinct laws",
        ));
    }
    let sides = [&s.walls.left, &s.walls.right, &s.walls.bottom, &s.walls.top];
    let walls = sides.map(|w| w.map(|w| w.mu));
    if !(s.method.flip.is_finite() && (0.0..=1.0).contains(&s.method.flip)) {
        return Err(InputError::new(
            "method.flip",
            s.method.flip,
            "must be in [0, 1] (1 = FLIP, 0 = PIC)",
        ));
    }
    positive("run.duration", s.run.duration)?;
    if !(s.run.safety > 0.0 && s.run.safety <= 1.0) {
        return Err(InputError::new(
            "run.safety",
            s.run.safety,
            "must be in (0, 1]",
        ));
    }
    let f = s.contact.separation_factor;
    if !(f.is_finite() && (0.5..=4.0).contains(&f)) {
        return Err(InputError::new(
            "contact.separation_factor",
            f,
            "must be in [0.5, 4]",
        ));
    }
    let separation = s.contact.separation_test.then(|| {
        grains_mpm::contact::touching_separation(shape, g.particles_per_cell) * f * g.cell_size
    });
    let setup = Setup {
        grid,
        shape,
        half_width: 0.5 / g.particles_per_cell as f64,
        scheme,
        flip: s.method.flip,
        pass1_to_particles: s.method.pass1_to_particles,
        materials: s.materials.clone(),
        bodies,
        contact,
        separation,
        walls,
        gravity: DVec2::from(s.gravity),
    };
    setup.validate()?;
    let dt_critical = timestep::critical_dt(&setup, &particles);
    let dt = time_step(
        s.run.dt,
        s.run.safety,
        dt_critical,
        "h / (c + |v|max), c the fastest dilatational wave speed",
    )?;
    let steps = (s.run.duration / dt).ceil() as u64;
    s.output.validate(&super::CAPABILITIES, s.run.duration)?;
    check_references(s, &names)?;
    Ok(Assembled {
        setup,
        particles,
        areas,
        velocities,
        counts,
        dt,
        dt_critical,
        steps,
    })
}

fn check_references(s: &Scenario, names: &[&str]) -> Result<(), InputError> {
    for (k, c) in s.checks.iter().enumerate() {
        let key = format!("check[{k}]");
        if let Some(b) = c.body() {
            if !names.contains(&b) {
                return Err(InputError::new(
                    format!("{key}.body"),
                    format!("\"{b}\""),
                    format!("must be one of {names:?}"),
                ));
            }
        }
        let tol = match c {
            CheckSpec::InitialEnergy { tolerance, .. }
            | CheckSpec::InitialMomentum { tolerance, .. }
            | CheckSpec::ImpactTangentialVelocity { tolerance, .. }
            | CheckSpec::ImpactSpin { tolerance, .. }
            | CheckSpec::Acceleration { tolerance, .. } => Some(("tolerance", *tolerance)),
            CheckSpec::EnergyLoss { max, .. } | CheckSpec::MomentumBetweenImpacts { max, .. } => {
                Some(("max", *max))
            }
            CheckSpec::Rotation { max_deg, .. } => Some(("max_deg", *max_deg)),
            CheckSpec::EnergyLossBelowReference { .. } => None,
        };
        if let Some((field, v)) = tol {
            positive(&format!("{key}.{field}"), v)?;
        }
        match c {
            CheckSpec::InitialMomentum { component, .. }
                if component != "x" && component != "y" =>
            {
                return Err(InputError::new(
                    format!("{key}.component"),
                    format!("\"{component}\""),
                    "must be \"x\" or \"y\"",
                ));
            }
            CheckSpec::EnergyLoss {
                after_impact: 0, ..
            }
            | CheckSpec::EnergyLossBelowReference {
                after_impact: 0, ..
            } => {
                return Err(InputError::new(
                    format!("{key}.after_impact"),
                    0,
                    "impacts count from 1",
                ));
            }
            CheckSpec::ImpactTangentialVelocity { impact: 0, .. }
            | CheckSpec::ImpactSpin { impact: 0, .. } => {
                return Err(InputError::new(
                    format!("{key}.impact"),
                    0,
                    "impacts count from 1",
                ));
            }
            CheckSpec::Acceleration { on, normal, .. } => {
                if !names.contains(&on.as_str()) {
                    return Err(InputError::new(
                        format!("{key}.on"),
                        format!("\"{on}\""),
                        format!("must be one of {names:?}"),
                    ));
                }
                let n = DVec2::from(*normal);
                if !(n.is_finite() && n.length() > 0.0) {
                    return Err(InputError::new(
                        format!("{key}.normal"),
                        format!("{normal:?}"),
                        "must be a finite non-zero vector",
                    ));
                }
                if s.gravity == [0.0, 0.0] {
                    return Err(InputError::new(
                        "gravity",
                        "[0, 0]",
                        format!("{key} needs gravity"),
                    ));
                }
            }
            _ => {}
        }
    }
    Ok(())
}
