//! `grains check` for FEM–DEM: the charge's elements and the ring's particles are
//! counted from the scenario (mesh sizes, packing file lines, the lattice's fill) before
//! anything is built; then the scenario is assembled and its mass ratio and steps
//! derived.

use super::assemble::{assemble_with, on_demand, Assembled, Unmade};
use super::probes::{fill_to_burster_check, gurney_velocity};
use super::scenario::{CheckSpec, PackingSpec, Scenario};
use crate::check::{Derived, Line};
use crate::estimate::{self, rate, Estimate};
use crate::packings::Cached;
use crate::source::Source;
use grains_fem::shell::milne_porous_gurney;
use std::f64::consts::PI;

/// Bytes per particle: as in DEM, plus the coupling's candidate pairs and the ring
/// analysis's copies (xue-2019 test 1 held 1.22 GB resident at 1,803,137 disks, 677 B
/// per disk, mid-run on 2026-11-27); bytes per element of the charge (state, node
/// shares and scratch).
const BYTES_PER_PARTICLE: u64 = 700;
const BYTES_PER_ELEMENT: u64 = 400;
/// Elements that cost as much as one particle in a step.
const ELEMENTS_PER_PARTICLE: u64 = 4;
/// Checkpoint bytes per particle (its fields, about three neighbour entries with their
/// springs and forces, its build position) and per element (the charge's fields with a
/// share of its nodes'). Test 1's first checkpoint: 440.1 MB for 1,803,137 disks and
/// 11,018 elements, 243 B per disk.
const CHECKPOINT_BYTES_PER_PARTICLE: u64 = 250;
const CHECKPOINT_BYTES_PER_ELEMENT: u64 = 250;

/// Particles and elements the scenario asks for, counted without building them.
pub fn size(s: &Scenario, src: &Source) -> (u64, u64) {
    let c = &s.charge;
    // A triangle of edge h has area √3/4 h²; the mesh grades from the centre's size to
    // the edge's, so the mean of the two bounds the count within a factor of 2.
    let h = 0.5 * (c.mesh.size_edge + c.mesh.size_centre);
    // Sizes the assembly will refuse (naming their keys) count as nothing here.
    let counted = |v: f64| if v.is_finite() { v } else { 0.0 };
    let elements = if h > 0.0 {
        counted(PI * c.radius * c.radius / (3f64.sqrt() / 4.0 * h * h))
    } else {
        0.0
    };
    let particles = match &s.ring {
        None => 0.0,
        Some(r) => match &r.packing {
            PackingSpec::File { path } => {
                estimate::packing_lines(&src.base.join(path)).unwrap_or(0) as f64
            }
            // The spec's own estimate (its region at its target fraction); a spec that
            // cannot be read is reported by the assembly that follows.
            PackingSpec::Spec { spec } => grains_pack::parse(
                &std::fs::read_to_string(src.base.join(spec)).unwrap_or_default(),
                spec,
            )
            .ok()
            .and_then(|p| grains_pack::validate(&p).ok())
            .map_or(0.0, |v| v.estimated_particles),
            // A triangular lattice fills 0.9069 of the ring at pitch d0(1 + spread).
            PackingSpec::Lattice { d0, spread, .. } => {
                let pitch = d0 * (1.0 + spread);
                if pitch > 0.0 {
                    counted(
                        0.9069 * PI * (r.outer_radius.powi(2) - r.inner_radius.powi(2))
                            / (PI * 0.25 * pitch * pitch),
                    )
                } else {
                    0.0
                }
            }
        },
    };
    let clamp = |v: f64| {
        if v.is_finite() {
            v.min(1e19) as u64
        } else {
            u64::MAX
        }
    };
    (clamp(particles), clamp(elements))
}

/// The memory (bytes) of a run of `particles` grains and a charge of `elements`.
pub fn memory(particles: u64, elements: u64) -> u64 {
    particles
        .saturating_mul(BYTES_PER_PARTICLE)
        .saturating_add(elements.saturating_mul(BYTES_PER_ELEMENT))
        .saturating_add(1 << 20)
}

/// The memory a run needs, checked against what is available, before anything is built.
pub fn fits(s: &Scenario, src: &Source, threads: usize) -> Result<(), String> {
    let (n, e) = size(s, src);
    Estimate::new(n, 0, memory(n, e), rate::FEM_DEM, threads)
        .fits_memory(&format!("{}: ring and charge", src.origin))
}

/// The smallest step of the run: the step at the start, before the springs in contact
/// multiply and the gas's sound speed changes.
pub fn dt_initial(s: &Scenario, a: &Assembled) -> f64 {
    let mut dt = a.fem.safety * a.dt_charge;
    if let Some(r) = &a.ring {
        dt = dt.min(r.dt(s.run.coupling_safety));
    }
    dt
}

/// What `grains check` prints for a FEM–DEM scenario.
pub fn derived(s: &Scenario, src: &Source, threads: usize) -> Result<Derived, String> {
    fits(s, src, threads)?;
    let od = on_demand(s, &src.base).map_err(|e| format!("{}: {e}", src.origin))?;
    let a =
        assemble_with(s, &src.base, Unmade::Preview).map_err(|e| format!("{}: {e}", src.origin))?;
    let x = &a.fem.explosive;
    let mut d = Derived {
        lines: Derived::head(&s.name, "fem_dem", &s.description),
        ..Default::default()
    };
    d.lines.extend([
        Line::new(
            "explosive",
            x.name.clone(),
            format!("{} ({})", x.name, x.source),
        ),
        Line::quiet("explosive_source", x.source.clone()),
        Line::new(
            "charge_radius",
            s.charge.radius,
            format!("{:.4e} m", s.charge.radius),
        ),
        Line::new(
            "charge_mass",
            a.charge_mass,
            format!("{:.5e} kg/m", a.charge_mass),
        ),
        Line::new(
            "charge_elements",
            a.mesh.tris.len(),
            format!(
                "{} triangles, {} nodes, {} boundary edges",
                a.mesh.tris.len(),
                a.mesh.nodes.len(),
                a.mesh.boundary.len()
            ),
        ),
        Line::quiet("charge_nodes", a.mesh.nodes.len()),
        Line::quiet("boundary_edges", a.mesh.boundary.len()),
    ]);
    let (emin, emax) = a.mesh.edge_range();
    d.lines.extend([
        Line::new(
            "mesh_edges",
            serde_json::json!([emin, emax]),
            format!(
                "{emin:.3e} to {emax:.3e} m, smallest angle {:.1}°",
                a.mesh.min_angle().to_degrees()
            ),
        ),
        Line::quiet("mesh_edge_min", emin),
        Line::quiet("mesh_edge_max", emax),
        Line::quiet("mesh_min_angle_deg", a.mesh.min_angle().to_degrees()),
        Line::quiet("cj_volume", x.v_cj()),
        Line::quiet("jwl_pressure_at_cj", x.jwl_cj_pressure()),
        Line::quiet("dt_charge", a.fem.safety * a.dt_charge),
    ]);
    let mut fb = f64::NAN;
    let n = match &a.ring {
        Some(r) => {
            fb = r.mass / a.charge_mass;
            let (ri, ro) = r.radii;
            let area: f64 = r.particles.radius.iter().map(|v| PI * v * v).sum();
            let phi = area / (PI * (ro * ro - ri * ri));
            let bulk = r.mass / (PI * (ro * ro - ri * ri));
            let milne = milne_porous_gurney(&a.fem.explosive, fb, bulk, phi)
                .map_or(f64::NAN, |m| m.velocity);
            d.lines.extend([
                Line::new(
                    "particles",
                    r.particles.len(),
                    format!(
                        "{} disks of mean diameter {:.4e} m, area fraction {phi:.4}",
                        r.particles.len(),
                        r.mean_diameter
                    ),
                ),
                Line::quiet("ring_area_fraction", phi),
                Line::quiet("mean_diameter", r.mean_diameter),
                Line::new("ring_mass", r.mass, format!("{:.5e} kg/m", r.mass)),
                Line::new("fill_to_burster_ratio", fb, format!("{fb:.4}")),
                Line::new(
                    "gurney_velocity",
                    gurney_velocity(&a.fem, fb),
                    format!(
                        "{:.0} m/s (classic cylindrical Gurney at this F/B)",
                        gurney_velocity(&a.fem, fb)
                    ),
                ),
                Line::new(
                    "milne_porous_gurney",
                    milne,
                    format!(
                        "{milne:.0} m/s (Milne's porous-shell Gurney, xue-2019 Eq. 9, as \
                         reconstructed: the gas fills the ring's pores first, losing half its \
                         work meanwhile)"
                    ),
                ),
                Line::new(
                    "coupling_stiffness",
                    r.stiffness,
                    format!("{:.4e} N/m per m", r.stiffness),
                ),
                Line::quiet("dt_particles", r.dt_dem),
                Line::quiet("dt_particles_critical", r.dt_critical),
                Line::quiet("dt_penalty_critical", r.dt_penalty),
                Line::quiet("skin", r.setup.skin),
            ]);
            if let Some(od) = &od {
                let ready = od.state() == Cached::Ready;
                d.lines.extend([
                    Line::new(
                        "packing",
                        od.file().display().to_string(),
                        if ready {
                            format!("{} (cached)", od.file().display())
                        } else {
                            format!(
                                "not made yet: `grains run` makes it first ({} disks sized from the spec) → {}",
                                r.particles.len(),
                                od.file().display()
                            )
                        },
                    ),
                    Line::quiet("packing_cached", ready),
                    Line::quiet("packing_key", format!("{:016x}", od.key)),
                ]);
            }
            r.particles.len() as u64
        }
        None => {
            d.lines
                .push(Line::new("particles", 0, "none (a bare charge)"));
            0
        }
    };
    let dt = dt_initial(s, &a);
    let steps = (s.run.duration / dt).ceil() as u64;
    let steps_max = (s.run.duration / (s.run.min_dt_ratio * dt)).ceil() as u64 + 1;
    d.lines.extend([
        Line::new(
            "dt_initial",
            dt,
            format!("{dt:.4e} s (the step adapts to the charge and the contacts)"),
        ),
        Line::new(
            "duration",
            s.run.duration,
            format!("{:.4e} s", s.run.duration),
        ),
        Line::new(
            "steps_estimate",
            steps,
            format!("≈ {steps} at the initial step"),
        ),
        Line::new(
            "steps",
            steps_max,
            format!(
                "at most {steps_max}: the run stops if its step falls below run.min_dt_ratio = {} of the initial one",
                s.run.min_dt_ratio
            ),
        ),
    ]);
    if let Some(k) = s.output.checkpoint_every {
        let size = n * CHECKPOINT_BYTES_PER_PARTICLE
            + a.mesh.tris.len() as u64 * CHECKPOINT_BYTES_PER_ELEMENT;
        d.lines.push(Line::new(
            "checkpoint_bytes",
            size,
            format!(
                "every {k} steps (about {} over the run), ≈ {} each, kept as checkpoint.bin beside the outputs; `grains resume` goes on from it",
                steps / k.max(1),
                estimate::bytes(size)
            ),
        ));
    }
    for c in &s.checks {
        if let CheckSpec::FillToBurster {
            expected,
            tolerance,
            paper,
        } = *c
        {
            d.checks
                .push(fill_to_burster_check(fb, expected, tolerance, paper));
        }
    }
    d.cost(&cost(n, a.mesh.tris.len() as u64, steps, threads));
    Ok(d)
}

/// What a run of `n` particles and `elements` triangles over `steps` steps costs.
pub fn cost(n: u64, elements: u64, steps: u64, threads: usize) -> Estimate {
    let work = n + elements / ELEMENTS_PER_PARTICLE;
    Estimate::new(work, steps, memory(n, elements), rate::FEM_DEM, threads)
}
