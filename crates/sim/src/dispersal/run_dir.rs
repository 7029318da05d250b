//! `grains analyze RUN_DIR [--times ...]`: the dispersal analysis of a finished run,
//! read from its `scenario.toml` and `frames/` (particles with their mass and contact
//! stress, the charge's mesh for its extent), written under `--out` (default
//! `RUN_DIR/analysis`): `frames/fields_*.vts`, `plots/dispersal/`, `analysis.json`.
//!
//! Every frame is analysed (as the run's `[analysis.dispersal]` would inline), with the
//! maps at the frames nearest its `times` (or at the last frame); `--times` puts the
//! maps at the frames nearest those times instead. Analyses made inline between frames
//! (`every`) have no frame to be repeated from.
//!
//! A FEM–DEM run's frames are also measured by the run's own band rule (`[analysis]`,
//! the history's `band_fraction`, `band_velocity`, `spall_velocity`), under `ring` in
//! `analysis.json`: a copy of the run directory whose `scenario.toml` names another
//! rule re-measures the run's band under it without running it again.

use super::analyst::{Analyst, Frame, Layout, Writes};
use super::settings::DispersalSettings;
use crate::blast;
use crate::scenario::{self, Scenario};
use crate::source::Source;
use glam::{DMat2, DVec2};
use grains_analysis::ring::{self as ring_analysis, Disks};
use grains_core::pvd::PvdSeries;
use grains_core::vtk::{find_array, read_appended_arrays, read_points_joined, ReadArray};
use serde_json::{json, Map, Value};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The particle file (and the charge's mesh, if any) of one frame.
struct FrameFiles {
    time: f64,
    particles: PathBuf,
    charge: Option<PathBuf>,
}

/// What the run's scenario says about the analysis.
struct RunInfo {
    name: String,
    settings: DispersalSettings,
    centre: DVec2,
    duration: f64,
    /// Grain density for frames written before frames carried the mass.
    density: Option<f64>,
    blast: Option<Box<blast::scenario::Scenario>>,
}

/// Whether `path` looks like a run directory (rather than a packing or frame file).
pub fn is_run_dir(path: &Path) -> bool {
    path.is_dir()
}

/// Analyses the run in `dir` into `out`, with the maps at the frames nearest `times`
/// (none: the scenario's). Returns the figures written to `out/analysis.json`.
pub fn analyze_run(
    dir: &Path,
    out: &Path,
    times: Option<&[f64]>,
) -> Result<Map<String, Value>, String> {
    let started = Instant::now();
    let info = run_info(dir)?;
    let frames = frame_files(dir)?;
    if let Some(bad) = times.and_then(|t| t.iter().find(|t| !t.is_finite())) {
        return Err(format!("--times: {bad} is not a time in seconds"));
    }
    if let (Some(t), Some(first), Some(end)) = (times, frames.first(), frames.last()) {
        // A time past the frames would be answered with the last frame, silently.
        let slack = 1e-9 * end.time.abs().max(1e-30);
        if let Some(bad) = t
            .iter()
            .find(|t| **t < first.time - slack || **t > end.time + slack)
        {
            return Err(format!(
                "--times: {} s is outside the run's frames, which span {:.4e} to {:.4e} s",
                grains_core::input::shown(*bad),
                first.time,
                end.time
            ));
        }
    }
    let chosen: Vec<f64> = times.map_or_else(|| info.settings.times.clone(), <[f64]>::to_vec);
    let nearest = |t: f64| {
        (0..frames.len())
            .min_by(|&a, &b| {
                (frames[a].time - t)
                    .abs()
                    .total_cmp(&(frames[b].time - t).abs())
            })
            .unwrap_or(0)
    };
    let mut maps = vec![false; frames.len()];
    for &t in &chosen {
        maps[nearest(t)] = true;
    }
    if chosen.is_empty() {
        if let Some(m) = maps.last_mut() {
            *m = true;
        }
    }
    let analyse: Vec<bool> = if !info.settings.every_frame() {
        maps.clone()
    } else {
        vec![true; frames.len()]
    };
    let mut analyst = Analyst::new(
        &info.name,
        info.settings.spec(),
        info.centre,
        info.settings.trace_time(info.duration),
        Layout::under(out),
    );
    let mut last: Option<Frame> = None;
    let mut ring_rows = Vec::new();
    let mut ring_d0 = None;
    for (k, f) in frames.iter().enumerate().filter(|(k, _)| analyse[*k]) {
        let frame = load(f, info.centre, info.density).map_err(|e| format!("{e:#}"))?;
        if let Some(s) = &info.blast {
            let d0 = *ring_d0.get_or_insert_with(|| frame.mean_diameter());
            ring_rows.push(ring_row(s, &frame, d0));
        }
        analyst
            .analyse(
                &frame,
                Writes {
                    fields: true,
                    maps: maps[k],
                },
            )
            .map_err(|e| format!("{}: {e:#}", f.particles.display()))?;
        last = Some(frame);
    }
    let mut figures = Map::new();
    figures.insert("source".into(), json!(dir.display().to_string()));
    figures.insert("frames".into(), json!(frames.len()));
    let spacing = match (frames.first(), frames.last()) {
        (Some(a), Some(b)) if frames.len() > 1 => (b.time - a.time) / (frames.len() - 1) as f64,
        _ => f64::NAN,
    };
    figures.insert("frame_spacing_s".into(), json!(spacing));
    figures.insert(
        "event_times_resolution".into(),
        json!(format!(
            "event times (reflection, arrest, meeting) are resolved only to the frame spacing, {spacing:.3e} s: the run's inline analysis, which sees every sample, is finer"
        )),
    );
    figures.insert(
        "dispersal".into(),
        analyst.finish().map_err(|e| format!("{e:#}"))?,
    );
    if let Some(s) = &info.blast {
        let r = blast::rule(&s.analysis);
        figures.insert(
            "ring".into(),
            json!({
                "rule": {
                    "band_fraction": r.band_fraction,
                    "radial_bin": r.radial_bin,
                    "sectors": r.sectors,
                },
                "frames": ring_rows,
            }),
        );
    }
    if let (Some(s), Some(f)) = (&info.blast, &last) {
        let mass: f64 = f.mass.iter().sum();
        if let Some(m) = blast::models::figures(s, mass, f.time) {
            figures.insert("models".into(), m);
        }
    }
    figures.insert("wall_time_s".into(), json!(started.elapsed().as_secs_f64()));
    let path = out.join("analysis.json");
    grains_core::json::write_json_pretty(&path, &Value::Object(figures.clone()))
        .map_err(|e| e.to_string())?;
    Ok(figures)
}

/// The history's ring figures at one frame, by the run's own rule (`[analysis]`) about
/// the charge's centre with mean diameter `d0`. The pressure front is left out: the run
/// reads it from the contacts' elastic forces, which a frame does not carry.
fn ring_row(s: &blast::scenario::Scenario, f: &Frame, d0: f64) -> Value {
    let rule = blast::rule(&s.analysis);
    let r_in = s.ring.as_ref().map_or(0.0, |r| r.inner_radius);
    let disks = Disks {
        pos: &f.pos,
        vel: &f.vel,
        radius: &f.radius,
        mass: &f.mass,
    };
    let centre = DVec2::from(s.charge.centre);
    let ns = ring_analysis::sectors(&rule, r_in, d0);
    let g = ring_analysis::measure(&rule, ns, disks, centre, d0, &[]);
    json!({
        "time": f.time,
        "band_fraction": g.band_fraction,
        "band_velocity": g.band_velocity,
        "spall_velocity": g.spall_velocity,
        "band_outer": g.band_outer,
        "mean_velocity": g.mean_velocity,
        "inner_radius": g.inner,
        "outer_radius": g.outer,
    })
}

/// The scenario's name, analysis settings, centre and duration.
fn run_info(dir: &Path) -> Result<RunInfo, String> {
    let file = dir.join("scenario.toml");
    if !file.exists() {
        return Err(format!(
            "{}: not a run directory (no scenario.toml); `grains analyze` takes a run \
             directory, a packing file or a DEM frame (.vtp)",
            dir.display()
        ));
    }
    let src = Source::read(&file)?;
    match scenario::parse(&src)? {
        Scenario::FemDem(s) => {
            let settings = s.analysis.dispersal.clone().unwrap_or_default();
            let density = s.ring.as_ref().and_then(|r| {
                s.materials
                    .iter()
                    .find(|m| m.name == r.material)
                    .map(|m| m.density)
            });
            if s.ring.is_none() {
                return Err(format!(
                    "{}: a bare charge has no particles to analyse",
                    dir.display()
                ));
            }
            Ok(RunInfo {
                name: s.name.clone(),
                centre: settings
                    .centre
                    .map_or(DVec2::from(s.charge.centre), DVec2::from),
                duration: s.run.duration,
                settings,
                density,
                blast: Some(s),
            })
        }
        Scenario::Dem(s) => {
            let Some(settings) = s.dispersal.as_deref().cloned() else {
                return Err(format!(
                    "{}: a DEM run is analysed about the centre of its [dispersal] table, \
                     and this run's scenario has none",
                    dir.display()
                ));
            };
            let Some(c) = settings.centre else {
                return Err(format!(
                    "{}: [dispersal] needs `centre = [x, y]` for a DEM run",
                    dir.display()
                ));
            };
            Ok(RunInfo {
                name: s.name.clone(),
                centre: DVec2::from(c),
                duration: s.run.duration,
                density: (s.materials.len() == 1).then(|| s.materials[0].density),
                settings,
                blast: None,
            })
        }
        Scenario::Mpm(_) => Err(format!(
            "{}: the dispersal analysis reads DEM particles; this is an MPM run",
            dir.display()
        )),
        Scenario::Dem3(_) => Err(format!(
            "{}: the dispersal analysis is 2D; this is a 3D DEM run",
            dir.display()
        )),
    }
}

/// The frames of the run, in time order.
fn frame_files(dir: &Path) -> Result<Vec<FrameFiles>, String> {
    let frames = dir.join("frames");
    let pvd = frames.join("series.pvd");
    let series = PvdSeries::load(&pvd).map_err(|e| format!("{}: {e}", pvd.display()))?;
    let mut out: Vec<FrameFiles> = Vec::new();
    for e in series.entries() {
        let particles = match e.name.as_deref() {
            Some("particles") => true,
            None => e.file.starts_with("particles_"),
            _ => false,
        };
        let slot = match out.iter_mut().find(|f| f.time == e.time) {
            Some(f) => f,
            None => {
                out.push(FrameFiles {
                    time: e.time,
                    particles: PathBuf::new(),
                    charge: None,
                });
                out.last_mut().unwrap_or_else(|| unreachable!())
            }
        };
        if particles {
            slot.particles = frames.join(&e.file);
        } else if e.name.as_deref() == Some("charge") {
            slot.charge = Some(frames.join(&e.file));
        }
    }
    out.retain(|f| !f.particles.as_os_str().is_empty());
    out.sort_by(|a, b| a.time.total_cmp(&b.time));
    if out.is_empty() {
        return Err(format!("{}: lists no particle frames", pvd.display()));
    }
    Ok(out)
}

/// One frame's particles (and the charge's extent) from its files.
fn load(f: &FrameFiles, centre: DVec2, density: Option<f64>) -> anyhow::Result<Frame> {
    use anyhow::Context as _;
    let path = &f.particles;
    // A frame written under mpirun is a .pvtp over one piece per rank.
    let arrays = read_points_joined(path).with_context(|| format!("{}", path.display()))?;
    let get = |section: &str, name: &str| -> anyhow::Result<&ReadArray> {
        find_array(&arrays, section, name)
            .with_context(|| format!("{}: no {section} array `{name}`", path.display()))
    };
    let points = get("Points", "Points")?;
    let pos: Vec<DVec2> = points
        .values
        .chunks_exact(3)
        .map(|c| DVec2::new(c[0], c[1]))
        .collect();
    let vel: Vec<DVec2> = get("PointData", "velocity")?
        .values
        .chunks_exact(3)
        .map(|c| DVec2::new(c[0], c[1]))
        .collect();
    let radius = get("PointData", "radius")?.values.clone();
    let id: Vec<u32> = get("PointData", "id")?
        .values
        .iter()
        .map(|&v| v as u32)
        .collect();
    let mass = match (find_array(&arrays, "PointData", "mass"), density) {
        (Some(m), _) => m.values.clone(),
        (None, Some(rho)) => radius
            .iter()
            .map(|r| rho * std::f64::consts::PI * r * r)
            .collect(),
        (None, None) => anyhow::bail!(
            "{}: the frame carries no mass and the scenario no single grain density",
            path.display()
        ),
    };
    let stress = find_array(&arrays, "PointData", crate::dem::frames::STRESS_ARRAY).map(|a| {
        a.values
            .chunks_exact(9)
            .map(|c| DMat2::from_cols(DVec2::new(c[0], c[3]), DVec2::new(c[1], c[4])))
            .collect()
    });
    let charge_radius = match &f.charge {
        Some(c) => {
            let a = read_appended_arrays(c).with_context(|| format!("{}", c.display()))?;
            find_array(&a, "Points", "Points").map(|p| {
                p.values
                    .chunks_exact(3)
                    .map(|c| (DVec2::new(c[0], c[1]) - centre).length())
                    .fold(0.0, f64::max)
            })
        }
        None => None,
    };
    let n = pos.len();
    for (what, len) in [
        ("velocity", vel.len()),
        ("radius", radius.len()),
        ("id", id.len()),
        ("mass", mass.len()),
    ] {
        anyhow::ensure!(
            len == n,
            "{}: {len} {what} values for {n} points",
            path.display()
        );
    }
    Ok(Frame {
        time: f.time,
        id,
        pos,
        vel,
        radius,
        mass,
        stress,
        charge_radius,
    })
}

/// The figures that say most about a run's dispersal, one `key: value` line each.
pub fn main_figures(f: &Map<String, Value>) -> String {
    let d = &f["dispersal"];
    let fin = &d["final"];
    let sb = &d["shear_bands"];
    let lines = [
        ("frame_spacing_s", f["frame_spacing_s"].clone()),
        (
            "event_times_resolution",
            f["event_times_resolution"].clone(),
        ),
        ("analysed_times", d["analysed"].clone()),
        ("final_time", fin["time"].clone()),
        ("band_fraction", fin["band_fraction"].clone()),
        ("band_velocity", fin["band_velocity"].clone()),
        ("spall_velocity", fin["spall_velocity"].clone()),
        ("reflection_time", d["fronts"]["reflection"].clone()),
        ("arrest_time", d["fronts"]["arrest"].clone()),
        ("meeting_time", d["fronts"]["meeting"].clone()),
        ("shear_bands_clockwise", sb["clockwise"].clone()),
        ("shear_bands_anticlockwise", sb["anticlockwise"].clone()),
        ("shear_band_groups", sb["groups"].clone()),
        ("jets", d["jets"]["count"].clone()),
        ("classic_gurney", f["models"]["classic_gurney"].clone()),
        (
            "lossless_ceiling",
            f["models"]["lossless_ceiling"]["velocity"].clone(),
        ),
        (
            "milne_porous_gurney",
            f["models"]["milne_porous_gurney"]["velocity"].clone(),
        ),
    ];
    let mut s = String::new();
    for (k, v) in lines {
        if !v.is_null() {
            s.push_str(&format!("{k}: {v}\n"));
        }
    }
    s
}
