//! Files of the dispersal analysis: the fields as a ParaView structured grid (`.vts`)
//! and as polar maps (PNG) like xue-2019 Figs. 5–8, 11, 12; the R–t diagram of the
//! fronts (Fig. 6a); radial and azimuthal profiles and their spectra (Figs. 8c–d, 10,
//! 12d–f). Lengths on plots are in mm, times in µs, pressures in MPa.

use super::bands::BandMap;
use super::fields::PolarFields;
use super::fronts::{FrontHistory, FrontPhase};
use super::profiles::{AzimuthalProfile, RadialProfile};
use super::shear_bands::ShearBands;
use glam::DVec2;
use grains_core::plot::{ColourScale, LinePlot, Overlay, PlotError, PolarMap, Series};
use grains_core::vtk::{DataArray, StructuredGrid};
use std::path::{Path, PathBuf};

const MM: f64 = 1e3;
const US: f64 = 1e6;
const MPA: f64 = 1e-6;

/// The fields as a structured grid: (n_r + 1) × (n_θ + 1) points on the ring and sector
/// edges (the last sector edge repeats the first, closing the ring), one cell per bin.
/// Cell data: grains, mass, φ, velocity (vector), v_r, v_θ, dilation rate, shear rate,
/// vorticity, the strain rate's polar components (G_rr, G_θθ, G_rθ), and with stress
/// the pressure, shear stress and σ's polar components. Empty bins hold NaN velocity
/// and rates (ParaView shows them as "NaN colour").
pub fn fields_grid(fields: &PolarFields) -> StructuredGrid {
    let g = &fields.grid;
    let (nr, nt) = (g.n_r(), g.n_theta());
    let c = g.centre();
    let mut points = Vec::with_capacity((nr + 1) * (nt + 1));
    for j in 0..=nt {
        let u = DVec2::from_angle(j as f64 * g.dtheta());
        for i in 0..=nr {
            let p = c + g.r_edge(i) * u;
            points.push([p.x, p.y, 0.0]);
        }
    }
    let polar = |m: &[glam::DMat2]| {
        let mut v = Vec::with_capacity(3 * m.len());
        for (k, t) in m.iter().enumerate() {
            let (rr, tt, rt) = fields.polar_components(k, *t);
            v.extend_from_slice(&[rr, tt, rt]);
        }
        v
    };
    let strain: Vec<glam::DMat2> = fields
        .grad
        .iter()
        .map(|l| 0.5 * (*l + l.transpose()))
        .collect();
    let mut cell_data = vec![
        DataArray::scalar_i32("grains", fields.count.iter().map(|&c| c as i32).collect()),
        DataArray::scalar_f64("mass", fields.mass.clone()),
        DataArray::scalar_f64("packing_fraction", fields.phi.clone()),
        DataArray::vector2_f64("velocity", &fields.velocity),
        DataArray::scalar_f64("v_r", fields.v_r.clone()),
        DataArray::scalar_f64("v_theta", fields.v_theta.clone()),
        DataArray::scalar_f64("dilation_rate", fields.dilation.clone()),
        DataArray::scalar_f64("shear_rate", fields.shear_rate.clone()),
        DataArray::scalar_f64("vorticity", fields.vorticity.clone()),
        DataArray::vector3_f64("strain_rate_rr_tt_rt", polar(&strain)),
    ];
    if let Some(s) = &fields.stress {
        cell_data.push(DataArray::scalar_f64("pressure", s.pressure.clone()));
        cell_data.push(DataArray::scalar_f64("shear_stress", s.shear.clone()));
        cell_data.push(DataArray::vector3_f64("stress_rr_tt_rt", polar(&s.tensor)));
    }
    StructuredGrid {
        dims: [nr + 1, nt + 1, 1],
        points,
        point_data: Vec::new(),
        cell_data,
    }
}

/// Curves drawn over the maps.
#[derive(Clone, Copy, Debug, Default)]
pub struct MapOverlays<'a> {
    /// The band: R_comp(θ) drawn black.
    pub band: Option<&'a BandMap>,
    /// R_p(θ) per sector, drawn white (the paper's white outline of the shocked zone).
    pub pressure_front: Option<&'a [f64]>,
    /// Detected shear bands, drawn as spirals over the shear-rate map.
    pub shear_bands: Option<&'a ShearBands>,
}

/// One map: file suffix, caption, colour-bar label, scale, fixed range, values.
struct MapSpec {
    suffix: &'static str,
    name: &'static str,
    label: &'static str,
    scale: ColourScale,
    range: Option<(f64, f64)>,
    values: Vec<f64>,
}

/// Writes the polar maps of `fields` at `time` into `dir` as `{stem}_{field}.png`:
/// packing fraction, speed, radial velocity, dilation rate, shear rate and, with
/// stress, pressure. Returns the files written.
pub fn write_maps(
    dir: &Path,
    stem: &str,
    fields: &PolarFields,
    time: f64,
    charge_radius: Option<f64>,
    overlays: &MapOverlays,
) -> Result<Vec<PathBuf>, PlotError> {
    let g = &fields.grid;
    let mut maps = vec![
        MapSpec {
            suffix: "phi",
            name: "packing fraction",
            label: "packing fraction φ (−)",
            scale: ColourScale::Sequential,
            range: Some((0.0, 0.95)),
            values: fields
                .phi
                .iter()
                .zip(&fields.count)
                .map(|(p, c)| if *c > 0 || *p > 0.0 { *p } else { f64::NAN })
                .collect(),
        },
        MapSpec {
            suffix: "speed",
            name: "velocity magnitude",
            label: "speed |v| (m/s)",
            scale: ColourScale::Sequential,
            range: None,
            values: fields.velocity.iter().map(|v| v.length()).collect(),
        },
        MapSpec {
            suffix: "v_r",
            name: "radial velocity",
            label: "radial velocity v_r (m/s)",
            scale: ColourScale::Sequential,
            range: None,
            values: fields.v_r.clone(),
        },
        MapSpec {
            suffix: "dilation",
            name: "dilation rate D",
            label: "dilation rate D (1/s)",
            scale: ColourScale::Diverging,
            range: None,
            values: fields.dilation.clone(),
        },
        MapSpec {
            suffix: "shear_rate",
            name: "shear rate dγ/dt",
            label: "shear rate dγ/dt (1/s)",
            scale: ColourScale::Sequential,
            range: None,
            values: fields.shear_rate.clone(),
        },
    ];
    if let Some(p) = fields.pressure() {
        maps.push(MapSpec {
            suffix: "pressure",
            name: "pressure",
            label: "pressure p (MPa)",
            scale: ColourScale::Sequential,
            range: None,
            values: p
                .iter()
                .zip(&fields.mass)
                .map(|(p, m)| if *m > 0.0 { p * MPA } else { f64::NAN })
                .collect(),
        });
    }
    // View: the outermost ring holding material, with a margin.
    let outer = (0..g.len())
        .filter(|&k| fields.mass[k] > 0.0)
        .map(|k| g.r_edge(g.ring_sector(k).0 + 1))
        .fold(0.0, f64::max);
    let view = if outer > 0.0 { 1.05 * outer } else { g.r_max() };
    let band_curve: Vec<DVec2> = overlays
        .band
        .map(|b| {
            sector_curve(
                fields,
                &b.outer_radius
                    .iter()
                    .map(|r| r.unwrap_or(f64::NAN))
                    .collect::<Vec<_>>(),
            )
        })
        .unwrap_or_default();
    let front_curve: Vec<DVec2> = overlays
        .pressure_front
        .map(|r| sector_curve(fields, r))
        .unwrap_or_default();
    let spirals: Vec<Vec<DVec2>> = overlays.shear_bands.map(spiral_curves).unwrap_or_default();
    let edges = g.r_edges();
    let mut written = Vec::new();
    for m in maps {
        let title = format!("{stem}: {}, t = {:.2} µs", m.name, time * US);
        let mut overlay = Vec::new();
        if !band_curve.is_empty() {
            overlay.push(Overlay {
                points: &band_curve,
                closed: true,
                colour: [0, 0, 0],
                label: "R_comp (φ ≥ band threshold)",
            });
        }
        if !front_curve.is_empty() {
            overlay.push(Overlay {
                points: &front_curve,
                closed: true,
                colour: [255, 255, 255],
                label: "pressure front R_p",
            });
        }
        if m.suffix == "shear_rate" {
            for (k, s) in spirals.iter().enumerate() {
                overlay.push(Overlay {
                    points: s,
                    closed: false,
                    colour: [230, 0, 0],
                    label: if k == 0 { "detected shear bands" } else { "" },
                });
            }
        }
        let path = dir.join(format!("{stem}_{}.png", m.suffix));
        PolarMap {
            title: &title,
            value_label: m.label,
            r_edges: &edges,
            n_theta: g.n_theta(),
            values: &m.values,
            scale: m.scale,
            range: m.range,
            view_radius: view,
            charge_radius,
            overlays: overlay,
        }
        .write_png(&path)?;
        written.push(path);
    }
    Ok(written)
}

/// A closed curve through radius `r[j]` at each sector's mid-angle (skipping NaN),
/// relative to the centre.
fn sector_curve(fields: &PolarFields, r: &[f64]) -> Vec<DVec2> {
    let g = &fields.grid;
    r.iter()
        .enumerate()
        .filter(|(_, r)| r.is_finite())
        .map(|(j, r)| *r * DVec2::from_angle(g.theta_centre(j)))
        .collect()
}

/// Each detected band as a log spiral across the annulus searched.
fn spiral_curves(b: &ShearBands) -> Vec<Vec<DVec2>> {
    let (r0, r1) = b.annulus;
    let mut out = Vec::new();
    for (fam, sense) in [(&b.clockwise, -1.0), (&b.anticlockwise, 1.0)] {
        let tan = fam.angle.to_radians().tan();
        for &t0 in &fam.roots {
            out.push(
                (0..=20)
                    .map(|s| {
                        let r = r0 + (r1 - r0) * s as f64 / 20.0;
                        r * DVec2::from_angle(t0 + sense * tan * (r / r0).ln())
                    })
                    .collect(),
            );
        }
    }
    out
}

/// The R–t diagram of Fig. 6a: R_in, R_out, R_comp and the pressure front, drawn in one
/// colour per phase (PSF, RW, SSF, after), with the event times in the title.
pub fn plot_fronts(path: &Path, title: &str, h: &FrontHistory) -> Result<(), PlotError> {
    let t: Vec<f64> = h.frames.iter().map(|f| f.time * US).collect();
    let mm = |v: f64| v * MM;
    let col = |f: &dyn Fn(usize) -> Option<f64>| -> Vec<f64> {
        (0..t.len()).map(|k| f(k).map_or(f64::NAN, mm)).collect()
    };
    let r_in = col(&|k| Some(h.frames[k].r_in));
    let r_out = col(&|k| Some(h.frames[k].r_out));
    let r_comp = col(&|k| h.frames[k].band_outer);
    // Each phase's curve also takes the first point of the next, so the line is whole.
    let phase_curve = |want: FrontPhase| {
        col(&|k| {
            let here = h.phase[k] == Some(want);
            let joins = k > 0 && h.phase[k - 1] == Some(want);
            (here || joins)
                .then_some(h.frames[k].pressure_front)
                .flatten()
        })
    };
    let psf = phase_curve(FrontPhase::PrimaryShock);
    let rw = phase_curve(FrontPhase::Rarefaction);
    let ssf = phase_curve(FrontPhase::SecondaryShock);
    let merged = phase_curve(FrontPhase::Merged);
    let event = |name: &str, v: Option<f64>| v.map(|t| format!("{name} {:.1} µs", t * US));
    let events: Vec<String> = [
        event("reflection", h.reflection),
        event("arrest", h.arrest),
        event("meeting", h.meeting),
    ]
    .into_iter()
    .flatten()
    .collect();
    let title = if events.is_empty() {
        title.to_string()
    } else {
        format!("{title} ({})", events.join(", "))
    };
    LinePlot {
        title: &title,
        x_label: "t (µs)",
        y_label: "radius (mm)",
        // Curves without a single point (no stress: no R_p) stay out of the legend.
        series: [
            ("R_in", &r_in),
            ("R_out", &r_out),
            ("R_comp", &r_comp),
            ("R_p: primary shock (PSF)", &psf),
            ("R_p: rarefaction (RW)", &rw),
            ("R_p: secondary shock (SSF)", &ssf),
            ("R_p: after SSF meets R_comp", &merged),
        ]
        .into_iter()
        .filter(|(_, y)| y.iter().any(|v| v.is_finite()))
        .map(|(name, y)| Series { name, x: &t, y })
        .collect(),
        log_y: false,
        points: false,
    }
    .write_png_and_csv(path)
}

/// φ(r) and v_r(r) at several times (Figs. 8c–d, 10a): writes `{stem}_phi.png` and
/// `{stem}_v_r.png`.
pub fn plot_radial_profiles(
    dir: &Path,
    stem: &str,
    profiles: &[(f64, &RadialProfile)],
) -> Result<Vec<PathBuf>, PlotError> {
    let names: Vec<String> = profiles
        .iter()
        .map(|(t, _)| format!("t = {:.1} µs", t * US))
        .collect();
    let r: Vec<Vec<f64>> = profiles
        .iter()
        .map(|(_, p)| p.r.iter().map(|x| x * MM).collect())
        .collect();
    let mut out = Vec::new();
    for (suffix, label, get) in [
        (
            "phi",
            "packing fraction φ (−)",
            (|p: &RadialProfile| p.phi.clone()) as fn(&RadialProfile) -> Vec<f64>,
        ),
        ("v_r", "radial velocity v_r (m/s)", |p: &RadialProfile| {
            p.v_r.clone()
        }),
    ] {
        let y: Vec<Vec<f64>> = profiles.iter().map(|(_, p)| get(p)).collect();
        let path = dir.join(format!("{stem}_{suffix}.png"));
        LinePlot {
            title: &format!("{stem}: radial profiles, mean over sectors"),
            x_label: "r (mm)",
            y_label: label,
            series: (0..profiles.len())
                .map(|k| Series {
                    name: &names[k],
                    x: &r[k],
                    y: &y[k],
                })
                .collect(),
            log_y: false,
            points: false,
        }
        .write_png_and_csv(&path)?;
        out.push(path);
    }
    Ok(out)
}

/// The band's φ(θ), v_r(θ) and R_comp(θ) at one time (Figs. 10b, 12d–f), and their
/// spectra: writes `{stem}_phi.png`, `{stem}_v_r.png`, `{stem}_r_comp.png` and
/// `{stem}_spectra.png`.
pub fn plot_azimuthal(
    dir: &Path,
    stem: &str,
    time: f64,
    a: &AzimuthalProfile,
) -> Result<Vec<PathBuf>, PlotError> {
    let deg: Vec<f64> = a.theta.iter().map(|t| t.to_degrees()).collect();
    let r_mm: Vec<f64> = a.band_outer.iter().map(|r| r * MM).collect();
    let when = format!("t = {:.1} µs", time * US);
    let mut out = Vec::new();
    for (suffix, what, label, y) in [
        (
            "phi",
            "band packing fraction",
            "φ, radial mean over the band (−)",
            &a.phi,
        ),
        (
            "v_r",
            "band radial velocity",
            "v_r, radial mean over the band (m/s)",
            &a.v_r,
        ),
        ("r_comp", "band outer radius", "R_comp (mm)", &r_mm),
    ] {
        let path = dir.join(format!("{stem}_{suffix}.png"));
        LinePlot {
            title: &format!("{stem}: {what}, {when}"),
            x_label: "θ (degrees)",
            y_label: label,
            series: vec![Series {
                name: "",
                x: &deg,
                y,
            }],
            log_y: false,
            points: false,
        }
        .write_png_and_csv(&path)?;
        out.push(path);
    }
    // Spectra relative to each series' mean, modes 1.., log scale.
    let rel = |amp: &[f64]| -> Vec<f64> {
        let m = amp.first().copied().unwrap_or(0.0).abs();
        amp.iter()
            .skip(1)
            .map(|x| if m > 0.0 { x / m } else { f64::NAN })
            .collect()
    };
    let (sp, sv, sr) = (
        rel(&a.phi_spectrum.amplitude),
        rel(&a.v_r_spectrum.amplitude),
        rel(&a.band_outer_spectrum.amplitude),
    );
    let k: Vec<f64> = (1..=sp.len()).map(|k| k as f64).collect();
    let path = dir.join(format!("{stem}_spectra.png"));
    LinePlot {
        title: &format!("{stem}: azimuthal spectra of the band, {when}"),
        x_label: "mode number k",
        y_label: "amplitude / mean (−)",
        series: vec![
            Series {
                name: "φ(θ)",
                x: &k,
                y: &sp,
            },
            Series {
                name: "v_r(θ)",
                x: &k,
                y: &sv,
            },
            Series {
                name: "R_comp(θ)",
                x: &k,
                y: &sr,
            },
        ],
        log_y: true,
        points: true,
    }
    .write_png_and_csv(&path)?;
    out.push(path);
    Ok(out)
}
