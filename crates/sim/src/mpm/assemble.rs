//! Turns a parsed MPM scenario into the engine's inputs, validating every value on the
//! way. Nothing here writes to disk: a scenario that fails leaves no output behind.

use super::drive::VelocityTable;
use super::scenario::{LawName, Scenario};
use glam::{DMat2, DVec2};
use grains_core::input::{named_list, positive, time_step, InputError, Shown};
use grains_mpm::{
    timestep, Body, ContactLaw, ContactTable, Geometry, Grid, Motion, Particles, Setup,
    ShapeFunction, UpdateScheme,
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
    /// The shape each body was filled from (`minus` applied).
    pub geometry: Vec<Geometry>,
    /// Rigid bodies whose velocity follows a table.
    pub drives: Vec<(usize, VelocityTable)>,
    /// Time step (s).
    pub dt: f64,
    /// Largest stable time step (s).
    pub dt_critical: f64,
    /// Steps to run.
    pub steps: u64,
}

fn law(
    key: &str,
    name: LawName,
    mu: Option<f64>,
    strength: Option<f64>,
) -> Result<ContactLaw, InputError> {
    let friction = |mu: Option<f64>| {
        let mu = mu.unwrap_or(0.0);
        if mu.is_finite() && mu >= 0.0 {
            Ok(mu)
        } else {
            Err(InputError::new(
                format!("{key}.mu"),
                mu,
                "must be a finite number >= 0",
            ))
        }
    };
    if let (Some(s), false) = (strength, name == LawName::Bonded) {
        return Err(InputError::new(
            format!("{key}.strength"),
            s,
            "only a \"bonded\" law takes a strength",
        ));
    }
    match (name, mu) {
        (LawName::Coulomb, mu) => Ok(ContactLaw::Coulomb { mu: friction(mu)? }),
        (LawName::NoSlip, None) => Ok(ContactLaw::NoSlip),
        (LawName::NoSlip, Some(mu)) => Err(InputError::new(
            format!("{key}.mu"),
            mu,
            "only a \"coulomb\" or \"bonded\" law takes a friction coefficient",
        )),
        (LawName::Bonded, mu) => {
            let strength = strength.ok_or_else(|| {
                InputError::new(
                    format!("{key}.strength"),
                    "(missing)",
                    "a \"bonded\" law needs a bond strength (Pa, >= 0)",
                )
            })?;
            if !(strength.is_finite() && strength >= 0.0) {
                return Err(InputError::new(
                    format!("{key}.strength"),
                    strength,
                    "must be a finite number >= 0",
                ));
            }
            Ok(ContactLaw::Bonded {
                strength,
                mu: friction(mu)?,
            })
        }
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
    if let Some(l) = g.periodic_y {
        let height = g.hi[1] - g.lo[1];
        if !(l.is_finite() && (l - height).abs() <= 1e-9 * height) {
            return Err(InputError::new(
                "grid.periodic_y",
                l,
                format!(
                    "must equal the grid's height hi.y − lo.y = {} ({} cells of {})",
                    height.shown(),
                    cells[1],
                    g.cell_size.shown()
                ),
            ));
        }
        if cells[1] < 4 {
            return Err(InputError::new(
                "grid.periodic_y",
                l,
                format!(
                    "a periodic y needs at least 4 cells along y; the grid has {}",
                    cells[1]
                ),
            ));
        }
    }
    let grid = Grid {
        lo: DVec2::from(g.lo),
        h: g.cell_size,
        cells,
        periodic_y: g.periodic_y.is_some(),
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
        m.validate(&format!("material[{k}]"))?;
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
    let (mut shapes, mut drives) = (vec![], vec![]);
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
        let geometry = body_shape(s, k, &names, grid.period_y())?;
        if let Some(l) = grid.period_y() {
            let (lo, hi) = geometry.bounds();
            if hi.y - lo.y > l * (1.0 + 1e-9) {
                return Err(InputError::new(
                    format!("{key}.geometry"),
                    format!("{:?}", b.geometry),
                    format!(
                        "spans {} m along y, more than the periodic length grid.periodic_y = {} m (it would overlap itself)",
                        (hi.y - lo.y).shown(),
                        l.shown()
                    ),
                ));
            }
        }
        let (v, gradient, table) = motion(b, &key)?;
        if let Some(h) = &b.temperature {
            h.validate(&format!("{key}.temperature"))?;
            if b.rigid {
                return Err(InputError::new(
                    format!("{key}.temperature"),
                    format!("{h:?}"),
                    "only a free body has a temperature history (a rigid body has no strain)",
                ));
            }
        }
        // A shape far outside the grid would be filled point by point before the check
        // below could refuse it (a rectangle reaching to -1e308 never ends): one
        // reaching more than the grid's own size beyond it is refused by its bounds
        // (a periodic y wraps a body back, but only one at most a period tall).
        let (blo, bhi) = geometry.bounds();
        let size = DVec2::new(g.hi[0] - g.lo[0], g.hi[1] - g.lo[1]);
        let far = |k: usize| blo[k] < g.lo[k] - size[k] || bhi[k] > g.hi[k] + size[k];
        if !(blo.is_finite() && bhi.is_finite()) || far(0) || far(1) {
            return Err(InputError::new(
                format!("{key}.geometry"),
                format!("{:?}", b.geometry),
                format!(
                    "must lie inside the grid [{:?}, {:?}] (its bounds reach from ({:e}, {:e}) to ({:e}, {:e}))",
                    g.lo, g.hi, blo.x, blo.y, bhi.x, bhi.y
                ),
            ));
        }
        // Along a periodic y the points of a body across the seam come back inside.
        let points: Vec<DVec2> = geometry
            .fill(grid.lo, pitch)
            .into_iter()
            .map(|x| grid.wrap(x))
            .collect();
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
                let fused = b.rigid
                    && o.rigid
                    && o.velocity == b.velocity
                    && o.velocity_table == b.velocity_table;
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
        let area = geometry.area();
        let vol = area / points.len() as f64;
        let rho = s.materials[material].density();
        for x in &points {
            particles.push(k as u16, rho * vol, vol, *x, v + gradient.mul_vec2(*x));
        }
        bodies.push(Body {
            name: b.name.clone(),
            material,
            motion: if b.rigid {
                Motion::Prescribed(v)
            } else {
                Motion::Free
            },
            temperature: b.temperature.clone(),
        });
        if let Some(t) = table {
            drives.push((k, t));
        }
        shapes.push(geometry);
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
    let c = &s.contact;
    let mut contact = ContactTable::new(s.bodies.len(), law("contact", c.law, c.mu, c.strength)?);
    for (k, p) in s.contact.pair.iter().enumerate() {
        let key = format!("contact.pair[{k}]");
        // A name ending in '*' stands for every body whose name starts with the rest
        // (the grains of a packing).
        let matching = |name: &str| -> Result<Vec<usize>, InputError> {
            match name.strip_suffix('*') {
                Some(stem) => {
                    let list: Vec<usize> = (0..names.len())
                        .filter(|&b| names[b].starts_with(stem))
                        .collect();
                    if list.is_empty() {
                        return Err(InputError::new(
                            format!("{key}.bodies"),
                            format!("\"{name}\""),
                            format!("matches no body; must match one of {names:?}"),
                        ));
                    }
                    Ok(list)
                }
                None => Ok(vec![body_index(&format!("{key}.bodies"), name)?]),
            }
        };
        let (aa, bb) = (matching(&p.bodies[0])?, matching(&p.bodies[1])?);
        let pair_law = law(&key, p.law, p.mu, p.strength)?;
        for &a in &aa {
            for &b in &bb {
                if a == b {
                    return Err(InputError::new(
                        format!("{key}.bodies"),
                        format!("{:?}", p.bodies),
                        "must name two different bodies",
                    ));
                }
                contact.set(a, b, pair_law);
            }
        }
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
        crowd: s.contact.multi_body,
        separation,
        walls,
        gravity: DVec2::from(s.gravity),
        ledger: s.shear.is_some()
            || s.checks
                .iter()
                .any(|c| matches!(c, super::scenario::CheckSpec::EnergyLedger { .. })),
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
    super::check_input::validate(s, &setup, &shapes, &names)?;
    Ok(Assembled {
        setup,
        particles,
        areas,
        velocities,
        counts,
        geometry: shapes,
        drives,
        dt,
        dt_critical,
        steps,
    })
}

/// Body `k`'s shape: its geometry minus the shapes of the bodies its `minus` names (and,
/// along a periodic y of period `period`, minus their images a period up and down).
fn body_shape(
    s: &Scenario,
    k: usize,
    names: &[&str],
    period: Option<f64>,
) -> Result<Geometry, InputError> {
    let b = &s.bodies[k];
    let key = format!("body[{k}]");
    b.geometry.validate().map_err(|e| {
        InputError::new(format!("{key}.geometry"), e, "check the shape's parameters")
    })?;
    if b.minus.is_empty() {
        return Ok(b.geometry.clone());
    }
    let mut holes = Vec::new();
    for (j, name) in b.minus.iter().enumerate() {
        let key = format!("{key}.minus[{j}]");
        if name == "*" {
            holes.extend(
                (0..s.bodies.len())
                    .filter(|&o| o != k)
                    .map(|o| s.bodies[o].geometry.clone()),
            );
            continue;
        }
        match names.iter().position(|n| n == name) {
            Some(o) if o != k => holes.push(s.bodies[o].geometry.clone()),
            Some(_) => {
                return Err(InputError::new(
                    key,
                    format!("\"{name}\""),
                    "a body cannot be cut out of itself",
                ))
            }
            None => {
                return Err(InputError::new(
                    key,
                    format!("\"{name}\""),
                    format!("must be \"*\" or one of {names:?}"),
                ))
            }
        }
    }
    if let Some(l) = period {
        let images: Vec<Geometry> = holes
            .iter()
            .flat_map(|g| {
                [
                    g.translated(DVec2::new(0.0, l)),
                    g.translated(DVec2::new(0.0, -l)),
                ]
            })
            .collect();
        holes.extend(images);
    }
    let g = b.geometry.clone().minus(holes);
    g.validate()
        .map_err(|e| InputError::new(format!("{key}.minus"), e, "leave some of the region"))?;
    Ok(g)
}

/// Body `b`'s initial velocity, velocity gradient and (rigid bodies) velocity table.
fn motion(
    b: &super::scenario::BodySpec,
    key: &str,
) -> Result<(DVec2, DMat2, Option<VelocityTable>), InputError> {
    let mut v = DVec2::from(b.velocity);
    if !v.is_finite() {
        return Err(InputError::new(
            format!("{key}.velocity"),
            format!("{:?}", b.velocity),
            "must be finite",
        ));
    }
    let gradient = match b.velocity_gradient {
        None => DMat2::ZERO,
        Some(l) if b.rigid => {
            return Err(InputError::new(
                format!("{key}.velocity_gradient"),
                format!("{l:?}"),
                "only a free body takes a velocity gradient",
            ))
        }
        Some(l) if !l.iter().flatten().all(|x| x.is_finite()) => {
            return Err(InputError::new(
                format!("{key}.velocity_gradient"),
                format!("{l:?}"),
                "must be finite",
            ))
        }
        // Rows in the file, columns in glam: L·x = (L00 x + L01 y, L10 x + L11 y).
        Some(l) => DMat2::from_cols_array(&[l[0][0], l[1][0], l[0][1], l[1][1]]),
    };
    let table = match &b.velocity_table {
        None => None,
        Some(rows) => {
            let k = format!("{key}.velocity_table");
            if !b.rigid {
                return Err(InputError::new(
                    k,
                    format!("{rows:?}"),
                    "only a rigid body (rigid = true) follows a velocity table",
                ));
            }
            if b.velocity != [0.0, 0.0] {
                return Err(InputError::new(
                    format!("{key}.velocity"),
                    format!("{:?}", b.velocity),
                    "give a velocity or a velocity_table, not both",
                ));
            }
            let t = VelocityTable::new(&k, rows)?;
            v = t.at(0.0);
            Some(t)
        }
    };
    Ok((v, gradient, table))
}
