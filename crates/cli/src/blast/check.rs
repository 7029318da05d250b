//! `grains check` of a blast scenario: validate and print what a run would do.

use super::assemble::{assemble, Assembled};
use super::probes::{fill_to_burster_check, gurney_velocity};
use super::scenario::{self, CheckSpec, Scenario};
use crate::fail;
use serde_json::{json, Map, Value};
use std::path::Path;
use std::process::ExitCode;

/// Figures derived from an assembled scenario (also printed by `grains run`).
pub fn derived(s: &Scenario, a: &Assembled) -> Map<String, Value> {
    let mut m = Map::new();
    let x = &a.fem.explosive;
    m.insert("name".into(), s.name.clone().into());
    m.insert("engine".into(), "fem_dem".into());
    m.insert("explosive".into(), x.name.clone().into());
    m.insert("explosive_source".into(), x.source.clone().into());
    m.insert("charge_radius".into(), s.charge.radius.into());
    m.insert("charge_mass".into(), a.charge_mass.into());
    m.insert("charge_nodes".into(), a.mesh.nodes.len().into());
    m.insert("charge_elements".into(), a.mesh.tris.len().into());
    m.insert("boundary_edges".into(), a.mesh.boundary.len().into());
    let (emin, emax) = a.mesh.edge_range();
    m.insert("mesh_edge_min".into(), emin.into());
    m.insert("mesh_edge_max".into(), emax.into());
    m.insert(
        "mesh_min_angle_deg".into(),
        a.mesh.min_angle().to_degrees().into(),
    );
    m.insert("cj_volume".into(), x.v_cj().into());
    m.insert("jwl_pressure_at_cj".into(), x.jwl_cj_pressure().into());
    m.insert("dt_charge".into(), (a.fem.safety * a.dt_charge).into());
    m.insert("duration".into(), a.duration.into());
    let mut dt = a.fem.safety * a.dt_charge;
    match &a.ring {
        Some(r) => {
            let fb = r.mass / a.charge_mass;
            let (ri, ro) = r.radii;
            let area_fraction: f64 = r
                .particles
                .radius
                .iter()
                .map(|v| std::f64::consts::PI * v * v)
                .sum::<f64>()
                / (std::f64::consts::PI * (ro * ro - ri * ri));
            m.insert("particles".into(), r.particles.len().into());
            m.insert("ring_mass".into(), r.mass.into());
            m.insert("fill_to_burster_ratio".into(), fb.into());
            m.insert("ring_area_fraction".into(), area_fraction.into());
            m.insert("mean_diameter".into(), r.mean_diameter.into());
            m.insert("gurney_velocity".into(), gurney_velocity(&a.fem, fb).into());
            m.insert("coupling_stiffness".into(), r.stiffness.into());
            m.insert("dt_particles".into(), r.setup.dt.into());
            m.insert("dt_particles_critical".into(), r.dt_critical.into());
            m.insert("dt_penalty_critical".into(), r.dt_penalty.into());
            m.insert("skin".into(), r.setup.skin.into());
            dt = dt.min(r.dt(s.run.coupling_safety));
        }
        None => {
            m.insert("particles".into(), 0.into());
        }
    }
    m.insert("dt_initial".into(), dt.into());
    m.insert(
        "steps_estimate_upper".into(),
        ((a.duration / dt).ceil() as u64).into(),
    );
    m
}

/// Runs the command on scenario `text` read from `origin`.
pub fn cmd_check(text: &str, origin: &str, base: &Path, json_out: bool) -> ExitCode {
    let scn = match scenario::parse(text, origin) {
        Ok(v) => v,
        Err(e) => return fail(1, &e),
    };
    let asm = match assemble(&scn, base) {
        Ok(a) => a,
        Err(e) => return fail(1, &format!("{origin}: {e}")),
    };
    let mut d = derived(&scn, &asm);
    let fb = d
        .get("fill_to_burster_ratio")
        .and_then(Value::as_f64)
        .unwrap_or(f64::NAN);
    let checks: Vec<_> = scn
        .checks
        .iter()
        .filter_map(|c| match *c {
            CheckSpec::FillToBurster {
                expected,
                tolerance,
            } => Some(fill_to_burster_check(fb, expected, tolerance)),
            _ => None,
        })
        .collect();
    d.insert("checks".into(), json!(checks));
    if json_out {
        match serde_json::to_string_pretty(&d) {
            Ok(s) => println!("{s}"),
            Err(e) => return fail(1, &e.to_string()),
        }
    } else {
        for (k, v) in &d {
            if k != "checks" {
                println!("{k:28} {v}");
            }
        }
        for c in &checks {
            println!(
                "check {:22} measured {:.4} expected {:.4} ± {:.0} %  {}",
                c.name,
                c.measured,
                c.expected,
                100.0 * c.tolerance,
                if c.pass { "pass" } else { "FAIL" }
            );
        }
        println!("ok");
    }
    if checks.iter().all(|c| c.pass) {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(2)
    }
}
