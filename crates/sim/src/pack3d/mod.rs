//! `grains pack` for spheres: a spec with `dim = 3` ([`grains_pack::sphere_spec`])
//! packed to jamming by [`grains_pack::spheres::jam`]; writes the spec's copy,
//! `packing.txt` (`x y z r`, which a 3D scenario loads with `source = "file"`), a
//! frame and plots ([`output`]) and summary.json with the solid fraction, the
//! coordination and the fabric.

mod output;

use crate::pack::{spec_checks, Packed};
use grains_core::atomic::write_atomic;
use grains_pack::sphere_spec::{packing_text, SphereSpec};
use grains_pack::spheres::{jam, Container};
use serde_json::{json, Map};
use std::path::Path;
use std::time::Instant;

/// A sphere spec read and checked: the spec, its text and its container.
pub struct Prepared {
    /// The spec.
    pub spec: SphereSpec,
    /// Its text, copied into the output.
    pub text: String,
    /// The container's shape.
    pub container: Container,
}

/// Reads the spec at `path` if it is one for spheres (`dim = 3`), checking every value
/// (nothing written on failure); None for any other file.
pub fn prepare(path: &Path) -> Result<Option<Prepared>, String> {
    let origin = path.display().to_string();
    let text =
        std::fs::read_to_string(path).map_err(|e| format!("{origin}: cannot read spec: {e}"))?;
    let Ok(table) = toml::from_str::<toml::Table>(&text) else {
        return Ok(None);
    };
    if table.contains_key("engine") || !table.contains_key("dim") {
        return Ok(None);
    }
    let spec: SphereSpec = grains_core::input::parse_toml(&text, &origin)?;
    let container = spec.validate().map_err(|e| format!("{origin}: {e}"))?;
    Ok(Some(Prepared {
        spec,
        text,
        container,
    }))
}

/// Packs `p` into `out`.
pub fn pack(p: &Prepared, out: &Path) -> anyhow::Result<Packed> {
    use anyhow::Context;
    let started = Instant::now();
    let s = &p.spec;
    let packing = jam(
        s.sizes.count,
        s.sizes.diameter,
        s.sizes.ratio,
        p.container,
        s.seed,
    );
    std::fs::create_dir_all(out)
        .with_context(|| format!("cannot create output directory {}", out.display()))?;
    write_atomic(&out.join("spec.toml"), p.text.as_bytes())?;
    write_atomic(
        &out.join("packing.txt"),
        packing_text(s, &packing).as_bytes(),
    )?;
    output::write_outputs(out, &packing)?;
    let n = packing.radius.len();
    let mut fig = Map::new();
    for (k, v) in [
        ("particles", json!(n)),
        (
            "mean_diameter",
            json!(2.0 * packing.radius.iter().sum::<f64>() / n as f64),
        ),
        ("packing_fraction_bulk", json!(packing.phi_bulk)),
        ("packing_fraction_interior", json!(packing.phi_interior)),
        ("interior_margin_m", json!(packing.margin)),
        ("mean_coordination", json!(packing.coordination)),
        (
            "mean_coordination_interior",
            json!(packing.coordination_interior),
        ),
        ("isostaticity", json!(packing.isostaticity)),
        ("rattlers", json!(packing.rattlers)),
    ] {
        fig.insert(k.into(), v);
    }
    // The fabric tensor Σ n⊗n / N_c has trace 1: its eigenvalues are the deviator's
    // plus 1/3 (all 1/3 when isotropic).
    let fabric: Vec<f64> = packing
        .fabric_deviator
        .iter()
        .map(|d| d + 1.0 / 3.0)
        .collect();
    fig.insert("fabric_eigenvalues".into(), json!(fabric));
    fig.insert(
        "fabric_anisotropy".into(),
        json!(packing.fabric_deviator[0] - packing.fabric_deviator[2]),
    );
    match packing.container {
        Container::Box { size } => {
            fig.insert("container_size_m".into(), json!(size));
        }
        Container::Cylinder { radius, height } => {
            fig.insert("container_radius_m".into(), json!(radius));
            fig.insert("container_height_m".into(), json!(height));
        }
    }
    fig.insert("minimisations".into(), json!(packing.minimisations));
    let checks = spec_checks(&s.checks, &fig);
    let extra = [
        ("dimensions", json!(3)),
        ("wall_time_s", json!(started.elapsed().as_secs_f64())),
    ];
    let summary = crate::pack::write_summary(out, &s.name, &extra, fig, &checks)?;
    Ok(Packed {
        checks,
        summary,
        out: out.to_path_buf(),
    })
}
