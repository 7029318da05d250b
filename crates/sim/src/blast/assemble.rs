//! Turns a blast scenario into the engines' inputs, validating every value: the charge
//! (explosive, mesh, burn) for grains-fem, the ring (through the DEM front end's own
//! assembly) for grains-dem, and the coupling between them. Nothing is written here.

use super::scenario::{CheckSpec, PackingSpec, Scenario};
use crate::dem::scenario as dem_scn;
use crate::packings::{Cached, OnDemand};
use glam::DVec2;
use grains_core::input::{shown, InputError};
use grains_dem::{Particles, Setup};
use grains_fem::{mesh, Explosive, FemSetup, Mesh};
use grains_pack::ring::lattice_ring;
use std::path::Path;

/// A scenario ready to run.
pub struct Assembled {
    /// The charge's settings.
    pub fem: FemSetup,
    /// The charge's mesh.
    pub mesh: Mesh,
    /// The particle side, if there is a ring.
    pub ring: Option<RingPart>,
    /// Simulated time (s).
    pub duration: f64,
    /// Charge mass per unit thickness (kg/m), from the mesh.
    pub charge_mass: f64,
    /// Largest stable step of the charge at rest (s).
    pub dt_charge: f64,
}

/// The ring: DEM set-up and particles, and the coupling's constants.
pub struct RingPart {
    /// DEM configuration.
    pub setup: Setup,
    /// The particles' own step: `run.dem_safety` of their stable step (s).
    pub dt_dem: f64,
    /// The particles.
    pub particles: Particles,
    /// Largest stable DEM step (s).
    pub dt_critical: f64,
    /// Penalty stiffness K_pe (N/m per unit thickness).
    pub stiffness: f64,
    /// Largest stable step of the penalty contact (s).
    pub dt_penalty: f64,
    /// Ring mass (kg/m).
    pub mass: f64,
    /// Inner and outer radius (m).
    pub radii: (f64, f64),
    /// Mean diameter (m).
    pub mean_diameter: f64,
}

impl RingPart {
    /// Particle step: the DEM's own (already scaled by `run.dem_safety`), bounded by
    /// `coupling_safety` times the penalty contact's stable step.
    pub fn dt(&self, coupling_safety: f64) -> f64 {
        self.dt_dem.min(coupling_safety * self.dt_penalty)
    }
}

fn err(key: &str, value: impl Into<String>, allowed: impl Into<String>) -> String {
    InputError::new(key, value.into(), allowed).to_string()
}

fn positive(key: &str, v: f64) -> Result<(), String> {
    grains_core::input::positive(key, v).map_err(|e| e.to_string())
}

/// The explosive the scenario names, or a one-line error.
pub fn explosive(s: &Scenario) -> Result<Explosive, String> {
    let c = &s.charge;
    match (c.explosive.as_str(), &c.custom) {
        ("custom", Some(x)) => Ok(x.clone()),
        ("custom", None) => Err(err(
            "charge.custom",
            "(missing)",
            "required by explosive = \"custom\": a full [charge.custom] set",
        )),
        (name, custom) => {
            let known = Explosive::built_in(name).ok_or_else(|| {
                err(
                    "charge.explosive",
                    format!("\"{name}\""),
                    "unknown explosive: must be one of \"tnt\", \"tnt_llnl1985\", \"pe4\", \"custom\"",
                )
            })?;
            if custom.is_some() {
                return Err(err(
                    "charge.custom",
                    "(given)",
                    format!("only read with explosive = \"custom\", not \"{name}\""),
                ));
            }
            Ok(known)
        }
    }
}

/// What assembly does with a ring whose packing (`source = "spec"`) is not made yet.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unmade {
    /// Refuse: a run makes the packing first ([`crate::packings::OnDemand::ensure`]).
    Refuse,
    /// Stand in the disks the spec will make ([`grains_pack::preview`]): `grains check`.
    Preview,
}

/// Validates and assembles. `base` is the directory relative paths are read from.
pub fn assemble(s: &Scenario, base: &Path) -> Result<Assembled, String> {
    assemble_with(s, base, Unmade::Refuse)
}

/// The packing spec a ring names (`source = "spec"`), read, validated and checked
/// against the ring's annulus; `None` for other sources.
pub fn on_demand(s: &Scenario, base: &Path) -> Result<Option<OnDemand>, String> {
    let Some(r) = &s.ring else {
        return Ok(None);
    };
    let PackingSpec::Spec { spec } = &r.packing else {
        return Ok(None);
    };
    let od = OnDemand::open(&base.join(spec), "ring.packing.spec")?;
    od.fits_ring(
        "ring.packing.spec",
        r.inner_radius,
        r.outer_radius,
        s.charge.centre,
    )?;
    Ok(Some(od))
}

/// [`assemble`], with a choice of what to do with a packing not made yet.
pub fn assemble_with(s: &Scenario, base: &Path, unmade: Unmade) -> Result<Assembled, String> {
    if s.engine != "fem_dem" {
        return Err(err(
            "engine",
            format!("\"{}\"", s.engine),
            "must be \"fem_dem\"",
        ));
    }
    let c = &s.charge;
    let x = explosive(s)?;
    let key = if c.explosive == "custom" {
        "charge.custom"
    } else {
        "charge"
    };
    let centre = DVec2::from(c.centre);
    if !centre.is_finite() {
        return Err(err(
            "charge.centre",
            format!("{:?}", c.centre),
            "must be finite",
        ));
    }
    positive("charge.radius", c.radius)?;
    let fem = FemSetup::new(
        x,
        key,
        centre,
        c.radius,
        c.burn,
        c.viscosity,
        c.strength,
        c.damping,
        s.run.safety,
    )
    .map_err(|e| e.to_string())?;
    let mesh = mesh::circle(c.radius, centre, &c.mesh).map_err(|e| e.to_string())?;
    let charge_mass = fem.explosive.density * mesh.area();
    let dt_charge = grains_fem::Charge::new(&fem, &mesh).dt_stable;
    positive("run.duration", s.run.duration)?;
    for (key, v) in [
        ("run.dem_safety", s.run.dem_safety),
        ("run.coupling_safety", s.run.coupling_safety),
        ("run.min_dt_ratio", s.run.min_dt_ratio),
    ] {
        if !(v > 0.0 && v <= 1.0) {
            return Err(err(key, shown(v), "must be in (0, 1]"));
        }
    }
    s.output
        .validate(&super::CAPABILITIES, s.run.duration)
        .map_err(|e| e.to_string())?;
    let a = &s.analysis;
    if !(a.band_fraction > 0.0 && a.band_fraction < 1.0) {
        return Err(err(
            "analysis.band_fraction",
            shown(a.band_fraction),
            "must be in (0, 1)",
        ));
    }
    positive("analysis.radial_bin", a.radial_bin)?;
    positive("analysis.stressed_pressure", a.stressed_pressure)?;
    if let Some(n) = a.sectors {
        if !(4..=100_000).contains(&n) {
            return Err(err(
                "analysis.sectors",
                n.to_string(),
                "must be in 4..=100000",
            ));
        }
    }
    if !(a.terminal_window > 0.0 && a.terminal_window <= 1.0) {
        return Err(err(
            "analysis.terminal_window",
            shown(a.terminal_window),
            "must be in (0, 1]",
        ));
    }
    if let Some(d) = &a.dispersal {
        if s.ring.is_none() {
            return Err(err(
                "analysis.dispersal",
                "(a table)",
                "needs a [ring]: a bare charge has no particles to analyse",
            ));
        }
        d.validate("analysis.dispersal", s.run.duration)
            .map_err(|e| e.to_string())?;
    }

    let ring = match &s.ring {
        Some(_) => Some(ring_part(s, base, &fem, &mesh, unmade)?),
        None => None,
    };
    for (k, chk) in s.checks.iter().enumerate() {
        if let CheckSpec::ShearBandMode {
            mode,
            from,
            to,
            at_least,
            at_most,
        } = chk
        {
            shear_band_mode_valid(s, k, *mode, (*from, *to), (*at_least, *at_most))?;
            continue;
        }
        if let CheckSpec::ShearBandCount {
            from,
            to,
            at_least,
            at_most,
        } = chk
        {
            shear_band_window_valid(
                s,
                k,
                "shear_band_count",
                (*from, *to),
                (*at_least, *at_most),
                None,
            )?;
            continue;
        }
        if let CheckSpec::BandVelocityBracket { paper } = chk {
            positive(&format!("check[{k}].paper"), *paper)?;
            if ring.is_none() {
                return Err(err(
                    &format!("check[{k}].kind"),
                    "\"band_velocity_bracket\"",
                    "needs a [ring]",
                ));
            }
            continue;
        }
        let tol = chk.tolerance();
        if !(tol.is_finite() && tol > 0.0) {
            return Err(err(
                &format!("check[{k}].tolerance"),
                shown(tol),
                "must be a finite number > 0",
            ));
        }
        match chk {
            CheckSpec::BandVelocity { expected, .. }
            | CheckSpec::FillToBurster { expected, .. } => {
                positive(&format!("check[{k}].expected"), *expected)?;
                if let CheckSpec::FillToBurster {
                    paper: Some(paper), ..
                } = chk
                {
                    positive(&format!("check[{k}].paper"), *paper)?;
                }
                if ring.is_none() {
                    return Err(err(
                        &format!("check[{k}].kind"),
                        "band_velocity / fill_to_burster",
                        "needs a [ring]",
                    ));
                }
            }
            CheckSpec::EnergyConservation { .. } => {
                if ring.is_some() || c.damping > 0.0 {
                    return Err(err(
                        &format!("check[{k}].kind"),
                        "\"energy_conservation\"",
                        "needs a bare charge (no [ring]) and charge.damping = 0",
                    ));
                }
            }
            CheckSpec::RingEnergyTransfer { .. } => {
                if ring.is_none() {
                    return Err(err(
                        &format!("check[{k}].kind"),
                        "\"ring_energy_transfer\"",
                        "needs a [ring]",
                    ));
                }
            }
            CheckSpec::DetonationArrival { .. }
            | CheckSpec::BandVelocityBracket { .. }
            | CheckSpec::ShearBandMode { .. }
            | CheckSpec::ShearBandCount { .. } => {}
        }
    }
    Ok(Assembled {
        fem,
        mesh,
        ring,
        duration: s.run.duration,
        charge_mass,
        dt_charge,
    })
}

fn ring_part(
    s: &Scenario,
    base: &Path,
    fem: &FemSetup,
    mesh: &Mesh,
    unmade: Unmade,
) -> Result<RingPart, String> {
    let r = s.ring.as_ref().expect("ring present");
    let centre = DVec2::from(s.charge.centre);
    positive("ring.inner_radius", r.inner_radius)?;
    positive("ring.outer_radius", r.outer_radius)?;
    if s.charge.radius > r.inner_radius * (1.0 + 1e-9) {
        return Err(err(
            "charge.radius",
            shown(s.charge.radius),
            format!(
                "the charge overlaps the ring: must be <= ring.inner_radius = {} m",
                shown(r.inner_radius)
            ),
        ));
    }
    if r.outer_radius <= r.inner_radius {
        return Err(err(
            "ring.outer_radius",
            shown(r.outer_radius),
            format!("must be > ring.inner_radius = {} m", shown(r.inner_radius)),
        ));
    }
    let source = match &r.packing {
        PackingSpec::File { path } => {
            let full = base.join(path);
            if !full.is_file() {
                return Err(err(
                    "ring.packing.path",
                    format!("\"{path}\""),
                    format!(
                        "no such file ({}); packings come from `grains pack SPEC.toml`, which writes runs/<spec name>/packing.txt",
                        full.display()
                    ),
                ));
            }
            dem_scn::ParticleSource::File {
                material: r.material.clone(),
                path: path.clone(),
            }
        }
        PackingSpec::Spec { spec } => {
            let od = on_demand(s, base)?.expect("a spec source");
            match (od.state(), unmade) {
                (Cached::Ready, _) => dem_scn::ParticleSource::File {
                    material: r.material.clone(),
                    path: od.file().display().to_string(),
                },
                (_, Unmade::Preview) => {
                    let Some(pv) = od.preview() else {
                        return Err(err(
                            "ring.packing.spec",
                            format!("\"{spec}\""),
                            "a packing with protocol.start = \"lattice\" (a deposited packing is only sized once made: run `grains pack` on it and name the file with source = \"file\")",
                        ));
                    };
                    disk_list(&r.material, &pv.pos, &pv.radius)
                }
                (state, Unmade::Refuse) => {
                    return Err(format!(
                        "ring.packing.spec = \"{spec}\": the packing is not made ({}); `grains run` makes it",
                        match state {
                            Cached::Untrusted(u) => u.to_string(),
                            _ => "no file".to_string(),
                        }
                    ))
                }
            }
        }
        PackingSpec::Lattice {
            d0,
            spread,
            lining,
            seed,
        } => {
            positive("ring.packing.d0", *d0)?;
            if !(spread.is_finite() && (0.0..0.5).contains(spread)) {
                return Err(err(
                    "ring.packing.spread",
                    shown(*spread),
                    "must be in [0, 0.5)",
                ));
            }
            if !(lining.is_finite() && (0.0..=1.0).contains(lining)) {
                return Err(err(
                    "ring.packing.lining",
                    shown(*lining),
                    "must be in [0, 1]",
                ));
            }
            let width = r.outer_radius - r.inner_radius;
            if width < 2.0 * d0 * (1.0 + lining) {
                return Err(err(
                    "ring.packing.d0",
                    shown(*d0),
                    format!("too large for a ring {} m wide", shown(width)),
                ));
            }
            let disks = lattice_ring(
                centre,
                r.inner_radius,
                r.outer_radius,
                *d0,
                *spread,
                *lining,
                *seed,
            );
            if disks.pos.len() > 20_000_000 {
                return Err(err(
                    "ring.packing.d0",
                    shown(*d0),
                    "more than 20 million disks",
                ));
            }
            disk_list(&r.material, &disks.pos, &disks.radius)
        }
    };
    if let Some(sk) = s.run.skin {
        positive("run.skin", sk)?;
    }
    let half = 1.05 * r.outer_radius;
    let dem = dem_scn::Scenario {
        dim: None,
        engine: None,
        name: s.name.clone(),
        description: String::new(),
        domain: dem_scn::DomainSpec {
            lo: (centre - DVec2::splat(half)).to_array(),
            hi: (centre + DVec2::splat(half)).to_array(),
            periodic: [false, false],
        },
        gravity: [0.0, 0.0],
        contact: (&s.contact).into(),
        materials: s.materials.clone(),
        particles: vec![source],
        walls: Vec::new(),
        run: dem_scn::RunSpec {
            duration: s.run.duration,
            dt: None,
            safety: s.run.dem_safety,
            skin: s.run.skin,
            stop_kinetic_ratio: None,
            stop_rest_time: None,
        },
        output: Default::default(),
        checks: Vec::new(),
        figures: Vec::new(),
        dispersal: None,
        parallel: None,
    };
    // The DEM scenario names its own keys; say where they sit in this scenario. The
    // ring's material sits in `[ring]`, everything else in `[ring.packing]`.
    let in_ring = |e: InputError| {
        e.map_key("particles[0].material", "ring.material")
            .map_key("particles[0]", "ring.packing")
            .to_string()
    };
    let p = crate::dem::assemble::particles(&dem, base).map_err(in_ring)?;
    fits_the_ring(s, &p, centre)?;
    let asm = crate::dem::assemble::assemble_with(&dem, base, Some(p)).map_err(in_ring)?;
    let mut setup = asm.setup;
    let dt_dem = asm.dt;
    let p = asm.particles;
    let n = p.len();
    let mean_d = 2.0 * p.radius.iter().sum::<f64>() / n as f64;
    if s.run.skin.is_none() {
        setup.skin = 0.5 * mean_d;
    }
    // The ring spreads from the charge's centre: its neighbour list is judged in a frame
    // that expands from there, not rebuilt every ten steps for moving as a whole.
    setup.expanding_from = Some(centre);
    let mass: f64 = (0..n).map(|i| p.mass(i)).sum();

    let mat = p.material[0] as usize;
    let kn = setup.pairs.get(mat, mat).kn;
    let stiffness = match s.coupling.stiffness {
        Some(k) => {
            positive("coupling.stiffness", k)?;
            k
        }
        None => {
            positive("coupling.stiffness_ratio", s.coupling.stiffness_ratio)?;
            s.coupling.stiffness_ratio * kn
        }
    };
    let m_particle = (0..n).map(|i| p.mass(i)).fold(f64::INFINITY, f64::min);
    let m_node = boundary_node_mass(fem, mesh);
    let dt_penalty = 2.0 / (stiffness * (1.0 / m_particle + 1.0 / m_node)).sqrt();
    Ok(RingPart {
        setup,
        dt_dem,
        particles: p,
        dt_critical: asm.dt_critical,
        stiffness,
        dt_penalty,
        mass,
        radii: (r.inner_radius, r.outer_radius),
        mean_diameter: mean_d,
    })
}

/// Disks at rest as a DEM particle source.
fn disk_list(material: &str, pos: &[DVec2], radius: &[f64]) -> dem_scn::ParticleSource {
    dem_scn::ParticleSource::List {
        material: material.to_string(),
        disks: pos
            .iter()
            .zip(radius)
            .map(|(p, &radius)| dem_scn::DiskSpec {
                at: p.to_array(),
                radius,
                velocity: [0.0; 2],
                omega: 0.0,
            })
            .collect(),
    }
}

/// Smallest lumped mass of a boundary node.
fn boundary_node_mass(fem: &FemSetup, mesh: &Mesh) -> f64 {
    let mut m = vec![0.0; mesh.nodes.len()];
    for t in &mesh.tris {
        let p = t.map(|i| mesh.nodes[i as usize]);
        let a = grains_fem::mesh::signed_area(p[0], p[1], p[2]);
        for &i in t {
            m[i as usize] += fem.explosive.density * a / 3.0;
        }
    }
    mesh.boundary
        .iter()
        .map(|e| m[e[0] as usize])
        .fold(f64::INFINITY, f64::min)
}

/// Every disk must lie between the ring's circles (to 1 % of its radius), and none may
/// reach into the charge.
fn fits_the_ring(s: &Scenario, p: &Particles, centre: DVec2) -> Result<(), String> {
    let r = s.ring.as_ref().expect("ring present");
    let what = match &r.packing {
        PackingSpec::File { path } => format!("ring.packing.path = \"{path}\""),
        PackingSpec::Spec { spec } => format!("ring.packing.spec = \"{spec}\""),
        PackingSpec::Lattice { .. } => "ring.packing".to_string(),
    };
    for i in 0..p.len() {
        let rho = (p.pos[i] - centre).length();
        let rad = p.radius[i];
        let tol = 0.01 * rad;
        let (inner, outer) = (rho - rad, rho + rad);
        if inner < s.charge.radius - tol {
            return Err(format!(
                "{what}: disk {} at ({:.6e}, {:.6e}) with r = {:.4e} m reaches {:.6e} m from the centre: \
                 the charge (radius {} m) overlaps the ring",
                p.id[i],
                p.pos[i].x,
                p.pos[i].y,
                rad,
                inner,
                shown(s.charge.radius)
            ));
        }
        if inner < r.inner_radius - tol || outer > r.outer_radius + tol {
            return Err(format!(
                "{what}: disk {} at ({:.6e}, {:.6e}) with r = {:.4e} m spans {:.6e}..{:.6e} m from the centre: \
                 the packing does not fit the ring [{}, {}] m",
                p.id[i],
                p.pos[i].x,
                p.pos[i].y,
                rad,
                inner,
                outer,
                shown(r.inner_radius),
                shown(r.outer_radius)
            ));
        }
    }
    Ok(())
}

/// Checks a `shear_band_mode` check (the `k`-th).
fn shear_band_mode_valid(
    s: &Scenario,
    k: usize,
    mode: usize,
    window: (f64, f64),
    bounds: (Option<f64>, Option<f64>),
) -> Result<(), String> {
    if mode < 2 {
        return Err(err(
            &format!("check[{k}].mode"),
            mode.to_string(),
            "must be at least 2",
        ));
    }
    shear_band_window_valid(s, k, "shear_band_mode", window, bounds, Some(1.0))
}

/// Checks the window and the bound of a shear-band check (the `k`-th, of `kind`): one
/// of `at_least`/`at_most`, in [0, `max`] (a share: `max` = 1) or any finite value ≥ 0.
fn shear_band_window_valid(
    s: &Scenario,
    k: usize,
    kind: &str,
    (from, to): (f64, f64),
    bounds: (Option<f64>, Option<f64>),
    max: Option<f64>,
) -> Result<(), String> {
    let key = |f: &str| format!("check[{k}].{f}");
    if s.analysis.dispersal.is_none() {
        return Err(err(
            &key("kind"),
            format!("\"{kind}\""),
            "needs an [analysis.dispersal] table",
        ));
    }
    if !(from.is_finite() && to.is_finite() && 0.0 <= from && from < to) {
        return Err(err(
            &key("from/to"),
            format!("{}/{}", shown(from), shown(to)),
            "must satisfy 0 ≤ from < to",
        ));
    }
    let top = max.unwrap_or(f64::INFINITY);
    match bounds {
        (Some(b), None) | (None, Some(b)) if b.is_finite() && (0.0..=top).contains(&b) => Ok(()),
        (Some(b), None) | (None, Some(b)) => Err(err(
            &key("at_least/at_most"),
            shown(b),
            if max.is_some() {
                "must be a share in [0, 1]"
            } else {
                "must be a finite number ≥ 0"
            },
        )),
        _ => Err(err(
            &key("at_least/at_most"),
            "(both or neither)",
            "give exactly one of them",
        )),
    }
}
