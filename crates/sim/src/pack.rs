//! `grains pack SPEC.toml`: generate a packing, then analyse it and write the packing
//! file, a VTP frame, plots and summary.json.

use crate::analyze::{figures, write_outputs};
use grains_analysis::sample::{Sample, SampleKind};
use grains_core::atomic::write_atomic;
use grains_core::checks::Check;
use grains_pack::spec::PackSpec;
use serde_json::{json, Map, Value};
use std::path::{Path, PathBuf};
use std::time::Instant;

pub use grains_pack::Watch;

/// A packing made and analysed.
#[derive(Clone, Debug)]
pub struct Packed {
    /// Its checks with their verdicts.
    pub checks: Vec<Check>,
    /// What summary.json holds.
    pub summary: Map<String, Value>,
    /// Where the outputs are.
    pub out: PathBuf,
}

/// Reads and validates the spec at `path` (nothing written on failure): the spec, its
/// text and what follows from it.
pub fn prepare(path: &Path) -> Result<(PackSpec, String, grains_pack::Validated), String> {
    let origin = path.display().to_string();
    let text =
        std::fs::read_to_string(path).map_err(|e| format!("{origin}: cannot read spec: {e}"))?;
    if crate::scenario::kind_of(&text, &origin)? == crate::scenario::FileKind::Scenario {
        return Err(format!(
            "{origin}: this is a scenario, not a packing spec (it has no [sizes]); run it with `grains run {origin}`"
        ));
    }
    let spec = grains_pack::parse(&text, &origin)?;
    let validated = grains_pack::validate(&spec).map_err(|e| format!("{origin}: {e}"))?;
    crate::estimate::Estimate::new(
        validated.estimated_particles as u64,
        0,
        (validated.estimated_particles * 400.0) as u64,
        1.0,
        1,
    )
    .fits_memory(&format!("{origin}: sizes and domain"))?;
    Ok((spec, text, validated))
}

/// Makes the packing of `spec` (its `text`, validated as `v`) into `out`, reporting
/// progress through `watch`.
pub fn pack(
    spec: &PackSpec,
    text: &str,
    v: &grains_pack::Validated,
    out: &Path,
    watch: &mut dyn grains_pack::Watch,
) -> anyhow::Result<Packed> {
    let threads = rayon::current_num_threads();
    let (checks, summary) = run(spec, text, v, out, threads, watch)?;
    Ok(Packed {
        checks,
        summary,
        out: out.to_path_buf(),
    })
}

fn run(
    spec: &PackSpec,
    text: &str,
    v: &grains_pack::Validated,
    out: &Path,
    threads: usize,
    watch: &mut dyn grains_pack::Watch,
) -> anyhow::Result<(Vec<Check>, Map<String, Value>)> {
    use anyhow::Context;
    let started = Instant::now();
    let packing = grains_pack::pack(spec, v, watch);
    let seconds_pack = started.elapsed().as_secs_f64();
    std::fs::create_dir_all(out)
        .with_context(|| format!("cannot create output directory {}", out.display()))?;
    write_atomic(&out.join("spec.toml"), text.as_bytes())?;

    let sample = Sample {
        pos: packing.pos.clone(),
        radius: packing.radius.clone(),
        lining: packing.lining,
        region: Some(packing.region),
        kind: SampleKind::Packing,
    };
    let analysis = grains_analysis::analyze(&sample);
    let mut fig = figures(&sample, &analysis);
    let realised: Vec<(&str, f64)> = [
        "mean_diameter",
        "polydispersity",
        "packing_fraction_bulk",
        "psi6_local_mean_interior",
        "psi6_global_interior",
    ]
    .iter()
    .map(|k| (*k, fig.get(*k).and_then(Value::as_f64).unwrap_or(f64::NAN)))
    .collect();
    let file_text = grains_pack::output::packing_text(spec, &packing, &realised);
    write_atomic(&out.join("packing.txt"), file_text.as_bytes())?;
    write_outputs(out, &sample, &analysis, "packing")?;

    let st = &packing.stats;
    let checks = spec_checks(&spec.checks, &fig);
    let wall = started.elapsed().as_secs_f64();
    let nominal_delta = match spec.sizes {
        grains_pack::spec::SizeSpec::Gaussian { delta, .. }
        | grains_pack::spec::SizeSpec::Uniform { delta, .. }
        | grains_pack::spec::SizeSpec::Lognormal { delta, .. } => json!(delta),
        grains_pack::spec::SizeSpec::Bidisperse { .. } => Value::Null,
    };
    fig.insert("nominal_mean_diameter".into(), json!(v.d0));
    fig.insert("nominal_polydispersity".into(), nominal_delta);
    fig.insert("gaussian_truncated_mass".into(), json!(st.truncated_mass));
    fig.insert("deposited".into(), json!(st.deposited));
    fig.insert(
        "packing_fraction_after_deposit".into(),
        json!(st.fraction_after_deposit),
    );
    fig.insert("final_scale".into(), json!(st.final_scale));
    fig.insert("sweeps".into(), json!(st.sweeps));
    fig.insert(
        "packing_fraction_after_growth".into(),
        json!(st.fraction_after_growth),
    );
    fig.insert("swap_acceptance".into(), json!(st.swap_acceptance));
    fig.insert("growth_time_s".into(), json!(st.seconds_growth));
    fig.insert("swell_cycles".into(), json!(st.swell_cycles));
    fig.insert("minimiser_iterations".into(), json!(st.iterations));
    fig.insert("max_overlap_over_d0".into(), json!(st.max_overlap));
    fig.insert("deposit_time_s".into(), json!(st.seconds_deposit));
    fig.insert("swell_time_s".into(), json!(st.seconds_swell));
    let extra = [
        ("wall_time_s", json!(wall)),
        ("pack_time_s", json!(seconds_pack)),
        ("threads", json!(threads)),
    ];
    let summary = write_summary(out, &spec.name, &extra, fig, &checks)?;
    Ok((checks, summary))
}

/// Writes a packing's summary.json into `out` and returns it: its `name`, its status,
/// the main figures of `fig` ([`crate::analyze::MAIN_FIGURES`], those it has) beside
/// `extra`, then every figure and the `checks`.
pub(crate) fn write_summary(
    out: &Path,
    name: &str,
    extra: &[(&str, Value)],
    fig: Map<String, Value>,
    checks: &[Check],
) -> anyhow::Result<Map<String, Value>> {
    let mut summary = Map::new();
    summary.insert("name".into(), json!(name));
    summary.insert("status".into(), json!("completed"));
    for k in crate::analyze::MAIN_FIGURES {
        if let Some(v) = fig.get(k) {
            summary.insert(k.into(), v.clone());
        }
    }
    for (k, v) in extra {
        summary.insert((*k).into(), v.clone());
    }
    summary.insert("figures".into(), Value::Object(fig));
    summary.insert("checks".into(), serde_json::to_value(checks)?);
    grains_core::json::write_json_pretty(
        &out.join("summary.json"),
        &Value::Object(summary.clone()),
    )?;
    Ok(summary)
}

/// The spec's `[[check]]`s against the figures `fig` (a figure missing is NaN: fails).
pub fn spec_checks(specs: &[grains_pack::spec::CheckSpec], fig: &Map<String, Value>) -> Vec<Check> {
    specs
        .iter()
        .map(|c| {
            let measured = fig
                .get(&c.figure)
                .and_then(Value::as_f64)
                .unwrap_or(f64::NAN);
            let check = match (c.at_least, c.at_most) {
                (Some(lo), _) => Check::at_least(&c.figure, measured, lo),
                (_, Some(hi)) => Check::at_most(&c.figure, measured, hi),
                _ => Check::at_least(&c.figure, f64::NAN, 0.0),
            };
            if c.note.is_empty() {
                check
            } else {
                check.with_note(&c.note)
            }
        })
        .collect()
}
