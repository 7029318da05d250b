//! The dispersal analysis of one run: each analysed time in turn, then what needs them
//! all (fronts over time, radial profiles, jets traced back). The same code serves the
//! observer of a running simulation and `grains analyze RUN_DIR`, so both give the same
//! figures from the same particles.

use anyhow::Context as _;
use glam::{DMat2, DVec2};
use grains_analysis::dispersal::bands::{classify, Layer};
use grains_analysis::dispersal::{
    analyze_frame, fields_grid, front_history, jets, plot_azimuthal, plot_fronts,
    plot_radial_profiles, trace_jets, write_maps, DispersalSpec, FrameFronts, FrameSummary,
    JetOrigin, Jets, ParticleSet, RadialProfile, StressSource,
};
use grains_core::plot::{LinePlot, Series};
use grains_core::pvd::PvdSeries;
use serde_json::{json, Map, Value};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The particles at one time, as the analysis reads them (SI units, per unit thickness).
#[derive(Clone, Debug, Default)]
pub struct Frame {
    /// Time (s).
    pub time: f64,
    /// Stable ids.
    pub id: Vec<u32>,
    /// Centres (m).
    pub pos: Vec<DVec2>,
    /// Velocities (m/s).
    pub vel: Vec<DVec2>,
    /// Radii (m).
    pub radius: Vec<f64>,
    /// Masses (kg/m).
    pub mass: Vec<f64>,
    /// Each particle's contact stress (Pa, Love's average over the disk), if known.
    pub stress: Option<Vec<DMat2>>,
    /// The charge's farthest node from the centre (m), drawn on the maps.
    pub charge_radius: Option<f64>,
}

impl Frame {
    /// The slices the library reads.
    pub fn set(&self) -> anyhow::Result<ParticleSet<'_>> {
        Ok(ParticleSet::new(
            &self.pos,
            &self.vel,
            &self.radius,
            &self.mass,
            &self.id,
        )?)
    }

    /// Each particle's Σ a ⊗ f (N per unit thickness): its stress times its area.
    pub fn moments(&self) -> Option<Vec<DMat2>> {
        self.stress.as_ref().map(|s| {
            s.iter()
                .zip(&self.radius)
                .map(|(m, r)| *m * (std::f64::consts::PI * r * r))
                .collect()
        })
    }

    /// The same particles in ascending id: the analysis sums in index order, so every
    /// source of a frame (a serial run's storage order, a run on ranks, a frame's
    /// pieces joined in rank order) gives the same bits.
    pub fn in_id_order(&self) -> std::borrow::Cow<'_, Frame> {
        if self.id.windows(2).all(|w| w[0] < w[1]) {
            return std::borrow::Cow::Borrowed(self);
        }
        let mut order: Vec<usize> = (0..self.id.len()).collect();
        order.sort_unstable_by_key(|&k| self.id[k]);
        let pick = |v: &[DVec2]| order.iter().map(|&k| v[k]).collect();
        let pick_f = |v: &[f64]| order.iter().map(|&k| v[k]).collect();
        std::borrow::Cow::Owned(Frame {
            time: self.time,
            id: order.iter().map(|&k| self.id[k]).collect(),
            pos: pick(&self.pos),
            vel: pick(&self.vel),
            radius: pick_f(&self.radius),
            mass: pick_f(&self.mass),
            stress: self
                .stress
                .as_ref()
                .map(|s| order.iter().map(|&k| s[k]).collect()),
            charge_radius: self.charge_radius,
        })
    }

    /// Mean grain diameter, summed in id order so that any ordering of the same grains
    /// gives the same bits.
    pub fn mean_diameter(&self) -> f64 {
        let mut order: Vec<usize> = (0..self.id.len()).collect();
        order.sort_unstable_by_key(|&k| self.id[k]);
        let sum: f64 = order.iter().map(|&k| 2.0 * self.radius[k]).sum();
        sum / order.len().max(1) as f64
    }
}

/// What one analysed time writes besides its figures.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Writes {
    /// The fields as a structured grid (`.vts`), in the fields series.
    pub fields: bool,
    /// Polar maps and the band's azimuthal profiles (PNG).
    pub maps: bool,
}

/// Where the analysis writes: the fields beside the frames, the plots beside the run's.
#[derive(Clone, Debug)]
pub struct Layout {
    /// `fields_NNNNN.vts` and `fields.pvd`.
    pub frames: PathBuf,
    /// `fronts.png`, `radial_*.png`, `jets.png` and a folder per mapped time.
    pub plots: PathBuf,
}

impl Layout {
    /// The layout under a run (or analysis) directory: `frames/`, `plots/dispersal/`.
    pub fn under(root: &Path) -> Self {
        Layout {
            frames: root.join("frames"),
            plots: root.join("plots").join("dispersal"),
        }
    }
}

/// One analysed time.
struct Record {
    summary: FrameSummary,
    fronts: FrameFronts,
    radial: RadialProfile,
    fields_file: Option<String>,
    maps_dir: Option<String>,
}

/// A frame kept for tracing jets back to it.
struct Kept {
    frame: Frame,
    layers: Vec<Layer>,
}

/// The analysis of one run.
pub struct Analyst {
    name: String,
    spec: DispersalSpec,
    centre: DVec2,
    trace_time: f64,
    layout: Layout,
    d0: Option<f64>,
    series: Option<PvdSeries>,
    records: Vec<Record>,
    trace: Option<Kept>,
    last_jets: Option<(f64, Jets)>,
    seconds: f64,
    map_seconds: f64,
}

impl Analyst {
    /// An analysis named `name` (plot titles) with `spec`, about `centre`, writing into
    /// `layout`; jets are traced back to the analysed time nearest `trace_time`.
    pub fn new(
        name: &str,
        spec: DispersalSpec,
        centre: DVec2,
        trace_time: f64,
        layout: Layout,
    ) -> Self {
        Analyst {
            name: name.to_string(),
            spec,
            centre,
            trace_time,
            layout,
            d0: None,
            series: None,
            records: Vec::new(),
            trace: None,
            last_jets: None,
            seconds: 0.0,
            map_seconds: 0.0,
        }
    }

    /// Times analysed so far.
    pub fn analysed(&self) -> usize {
        self.records.len()
    }

    /// Wall-clock seconds spent analysing (files included).
    pub fn seconds(&self) -> f64 {
        self.seconds
    }

    /// Analyses `f`, writing what `writes` asks for.
    pub fn analyse(&mut self, f: &Frame, writes: Writes) -> anyhow::Result<()> {
        let started = Instant::now();
        let f = &*f.in_id_order();
        let d0 = *self.d0.get_or_insert_with(|| f.mean_diameter());
        let set = f.set()?;
        let moments = f.moments();
        let stress = moments.as_deref().map(StressSource::Particles);
        let a = analyze_frame(&self.spec, self.centre, d0, f.time, &set, stress)?;
        let mut fields_file = None;
        if writes.fields {
            std::fs::create_dir_all(&self.layout.frames)?;
            let k = self.series.as_ref().map_or(0, |s| s.entries().len());
            let file = format!("fields_{k:05}.vts");
            fields_grid(&a.fields).write(&self.layout.frames.join(&file))?;
            let frames = &self.layout.frames;
            self.series
                .get_or_insert_with(|| PvdSeries::new(&frames.join("fields.pvd")))
                .push(f.time, &file)?;
            fields_file = Some(file);
        }
        let mut maps_dir = None;
        if writes.maps {
            let drawing = Instant::now();
            let sub = format!("t_{:07.2}us", f.time * 1e6);
            let dir = self.layout.plots.join(&sub);
            std::fs::create_dir_all(&dir)
                .with_context(|| format!("cannot create {}", dir.display()))?;
            write_maps(
                &dir,
                &self.name,
                &a.fields,
                f.time,
                f.charge_radius,
                &a.overlays(),
            )?;
            plot_azimuthal(&dir, "band", f.time, &a.azimuthal)?;
            maps_dir = Some(sub);
            self.map_seconds += drawing.elapsed().as_secs_f64();
        }
        let found = jets(self.centre, &set, d0, &self.spec.jets);
        if self.last_jets.as_ref().is_none_or(|(t, _)| f.time >= *t) {
            self.last_jets = Some((f.time, found));
        }
        let closer = self.trace.as_ref().is_none_or(|k| {
            (f.time - self.trace_time).abs() < (k.frame.time - self.trace_time).abs()
        });
        if closer {
            self.trace = Some(Kept {
                frame: f.clone(),
                layers: classify(&a.fields, &a.band_map, &self.spec.band),
            });
        }
        self.records.push(Record {
            summary: a.summary(),
            fronts: a.fronts.clone(),
            radial: a.radial.clone(),
            fields_file,
            maps_dir,
        });
        self.seconds += started.elapsed().as_secs_f64();
        Ok(())
    }

    /// Writes the plots that need every analysed time (fronts, radial profiles, jets)
    /// and returns the figures for `summary.json`.
    pub fn finish(&mut self) -> anyhow::Result<Value> {
        let started = Instant::now();
        // In time order; of two analyses at one time (a frame and a sample), the one
        // with files.
        self.records
            .sort_by(|a, b| a.summary.time.total_cmp(&b.summary.time));
        self.records.dedup_by(|later, earlier| {
            let same = later.summary.time == earlier.summary.time;
            if same && earlier.fields_file.is_none() && earlier.maps_dir.is_none() {
                std::mem::swap(later, earlier);
            }
            same
        });
        let Some(d0) = self.d0 else {
            return Ok(json!({ "analysed": 0 }));
        };
        std::fs::create_dir_all(&self.layout.plots)
            .with_context(|| format!("cannot create {}", self.layout.plots.display()))?;
        let dr = self.spec.radial_bin * d0;
        let history = front_history(self.records.iter().map(|r| r.fronts.clone()).collect(), dr);
        plot_fronts(
            &self.layout.plots.join("fronts.png"),
            "Fronts, cf. Fig. 6a",
            &history,
        )?;
        let mapped: Vec<&Record> = self
            .records
            .iter()
            .filter(|r| r.maps_dir.is_some())
            .collect();
        let shown: Vec<&Record> = if mapped.len() >= 2 {
            mapped
        } else {
            spread(&self.records, 5)
        };
        let profiles: Vec<(f64, &RadialProfile)> =
            shown.iter().map(|r| (r.summary.time, &r.radial)).collect();
        plot_radial_profiles(&self.layout.plots, "radial", &profiles)?;
        let jets = self.jets()?;
        let frames: Vec<Value> = self
            .records
            .iter()
            .zip(&history.phase)
            .map(|(r, phase)| {
                let mut v = serde_json::to_value(&r.summary).unwrap_or(Value::Null);
                if let Value::Object(m) = &mut v {
                    m.insert("band_outer".into(), json!(r.fronts.band_outer));
                    m.insert("front_phase".into(), json!(phase));
                    m.insert("fields_file".into(), json!(r.fields_file));
                    m.insert("maps".into(), json!(r.maps_dir));
                }
                v
            })
            .collect();
        let last = self.records.last().map(|r| &r.summary);
        let shear = self
            .records
            .iter()
            .rev()
            .find_map(|r| r.summary.shear_bands.map(|s| (r.summary.time, s)));
        self.seconds += started.elapsed().as_secs_f64();
        let mut m = Map::new();
        m.insert("centre".into(), json!([self.centre.x, self.centre.y]));
        m.insert("d0".into(), json!(d0));
        m.insert("settings".into(), serde_json::to_value(self.spec)?);
        m.insert("analysed".into(), json!(self.records.len()));
        m.insert(
            "fronts".into(),
            json!({
                "reflection": history.reflection,
                "arrest": history.arrest,
                "meeting": history.meeting,
            }),
        );
        if let Some(s) = last {
            m.insert(
                "final".into(),
                json!({
                    "time": s.time,
                    "r_in": s.r_in,
                    "r_out": s.r_out,
                    "pressure_front": s.pressure_front,
                    "band_fraction": s.split.band.number_fraction,
                    "band_mass_fraction": s.split.band.mass_fraction,
                    "band_velocity": s.split.band.velocity,
                    "spall_fraction": s.split.spall.number_fraction,
                    "spall_velocity": s.split.spall.velocity,
                    "band_outer_radius": s.split.band_outer_radius,
                    "band_modes": s.band_modes,
                }),
            );
        }
        m.insert(
            "shear_bands".into(),
            match shear {
                Some((t, s)) => {
                    let mut v = serde_json::to_value(s)?;
                    v["time"] = json!(t);
                    v
                }
                None => Value::Null,
            },
        );
        m.insert("jets".into(), jets);
        m.insert("frames".into(), Value::Array(frames));
        m.insert("wall_time_s".into(), json!(self.seconds));
        m.insert("maps_wall_time_s".into(), json!(self.map_seconds));
        Ok(Value::Object(m))
    }

    /// The jets of the last analysed time traced back, as figures, and their plot.
    fn jets(&self) -> anyhow::Result<Value> {
        let Some((time, found)) = &self.last_jets else {
            return Ok(Value::Null);
        };
        let earlier = self.trace.as_ref().filter(|k| k.frame.time < *time);
        let origins: Vec<Option<JetOrigin>> = match earlier {
            Some(k) => trace_jets(found, self.centre, &k.frame.set()?, Some(&k.layers))
                .into_iter()
                .map(Some)
                .collect(),
            None => vec![None; found.jets.len()],
        };
        plot_jets(
            &self.layout.plots.join("jets.png"),
            &self.name,
            *time,
            found,
        )?;
        let list: Vec<Value> = found
            .jets
            .iter()
            .zip(&origins)
            .map(|(j, o)| {
                json!({
                    "theta_deg": j.theta.to_degrees(),
                    "tip_radius": j.tip_radius,
                    "height": j.height,
                    "width_deg": j.width.to_degrees(),
                    "grains": j.grains.len(),
                    "origin": o.as_ref().map(|o| json!({
                        "found": o.found,
                        "radius": o.radius,
                        "theta_deg": o.theta.to_degrees(),
                        "radial_spread": o.radial_spread,
                        "angular_spread_deg": o.angular_spread.to_degrees(),
                        "band": o.layers.map(|l| l[0]),
                        "transition": o.layers.map(|l| l[1]),
                        "spall": o.layers.map(|l| l[2]),
                    })),
                })
            })
            .collect();
        Ok(json!({
            "time": time,
            "count": found.jets.len(),
            "threshold": found.threshold,
            "traced_to": earlier.map(|k| k.frame.time),
            "jets": list,
        }))
    }
}

/// Up to `n` records spread evenly over the run, first and last included.
fn spread(records: &[Record], n: usize) -> Vec<&Record> {
    let len = records.len();
    if len <= n {
        return records.iter().collect();
    }
    let mut picked: Vec<usize> = (0..n).map(|k| k * (len - 1) / (n - 1)).collect();
    picked.dedup();
    picked.into_iter().map(|k| &records[k]).collect()
}

/// The outer envelope against angle with its baseline and the jets' spikes.
fn plot_jets(path: &Path, name: &str, time: f64, j: &Jets) -> anyhow::Result<()> {
    let n = j.envelope.len();
    let deg: Vec<f64> = (0..n)
        .map(|k| (k as f64 + 0.5) * 360.0 / n as f64)
        .collect();
    let mm = |v: &[f64]| v.iter().map(|x| x * 1e3).collect::<Vec<f64>>();
    let (env, base) = (mm(&j.envelope), mm(&j.baseline));
    // Each jet as a vertical stroke from the baseline to its tip, NaN between strokes.
    let (mut jx, mut jy) = (Vec::new(), Vec::new());
    for jet in &j.jets {
        let k = ((jet.theta / std::f64::consts::TAU * n as f64) as usize).min(n - 1);
        let t = jet.theta.to_degrees();
        jx.extend([t, t, f64::NAN]);
        jy.extend([base[k], jet.tip_radius * 1e3, f64::NAN]);
    }
    let title = format!(
        "{name}: outer envelope at t = {:.1} µs, {} jets (spikes > {:.2} mm)",
        time * 1e6,
        j.jets.len(),
        j.threshold * 1e3
    );
    let mut series = vec![
        Series {
            name: "envelope",
            x: &deg,
            y: &env,
        },
        Series {
            name: "baseline (running median)",
            x: &deg,
            y: &base,
        },
    ];
    if !jx.is_empty() {
        series.push(Series {
            name: "jets",
            x: &jx,
            y: &jy,
        });
    }
    LinePlot {
        title: &title,
        x_label: "θ (degrees)",
        y_label: "outer radius (mm)",
        series,
        log_y: false,
        points: false,
    }
    .write_png_and_csv(path)?;
    Ok(())
}
