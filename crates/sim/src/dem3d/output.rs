//! What a 3D run writes besides its history: ParaView frames of the spheres (3D points,
//! vector velocity, ω and force, the 3 × 3 contact stress), optionally a LAMMPS dump
//! beside each frame, and the plots: the history's
//! (as in 2D) and the final spheres seen from the side (x–z) and from above (x–y), with
//! the walls drawn.

use super::Dem3;
use crate::frames::Framed;
use glam::{DVec2, DVec3};
use grains_core::atomic::write_atomic_with;
use grains_core::plot::{time_label, Outline, ParticleMap};
use grains_core::vtk::{ArrayData, DataArray, PolyData};
use grains_dem3d::{diagnostics, Setup, State, WallShape};
use std::io::{self, Write};
use std::path::Path;

fn flat(v: &[DVec3]) -> Vec<f64> {
    v.iter().flat_map(|x| x.to_array()).collect()
}

/// The spheres as VTK vertices with their fields.
pub fn particles_polydata(setup: &Setup, s: &State) -> PolyData {
    let p = &s.particles;
    let stress = grains_dem3d::stress::particle_stress(setup, s);
    let contacts = diagnostics::contact_counts(setup, s);
    PolyData {
        points: p.pos.iter().map(|x| x.to_array()).collect(),
        verts: (0..p.len() as i64).map(|i| vec![i]).collect(),
        point_data: vec![
            DataArray::scalar_i64("id", p.id.iter().map(|&k| k as i64).collect()),
            DataArray::scalar_f64("radius", p.radius.clone()),
            DataArray::scalar_f64("mass", (0..p.len()).map(|i| p.mass(i)).collect()),
            DataArray::vector3_f64("velocity", flat(&p.vel)),
            DataArray::scalar_f64("speed", p.vel.iter().map(|v| v.length()).collect()),
            DataArray::vector3_f64("omega", flat(&p.omega)),
            DataArray::vector3_f64("force", flat(&p.force)),
            DataArray::scalar_i32("contacts", contacts.iter().map(|&c| c as i32).collect()),
            DataArray::scalar_i32("material", p.material.iter().map(|&m| m as i32).collect()),
            // Row-major 3 × 3, as ParaView reads a 9-component array.
            DataArray::new(
                crate::dem::frames::STRESS_ARRAY,
                9,
                ArrayData::F64(
                    stress
                        .iter()
                        .flat_map(|m| m.transpose().to_cols_array())
                        .collect(),
                ),
            ),
        ],
        ..PolyData::default()
    }
}

impl Framed for Dem3 {
    fn write_frame(&self, dir: &Path, k: usize) -> io::Result<Vec<(&'static str, String)>> {
        let name = format!("particles_{k:05}.vtp");
        particles_polydata(&self.setup, &self.state).write(&dir.join(&name))?;
        if self.lammps_dump {
            let dump = dir.join(format!("particles_{k:05}.dump"));
            write_atomic_with(&dump, |w| lammps_dump(w, &self.setup, &self.state))?;
        }
        Ok(vec![("particles", name)])
    }
}

/// The columns of the 3D dump, as LAMMPS's `dump custom` names them.
pub const DUMP_COLUMNS: &str = "id type x y z vx vy vz omegax omegay omegaz radius fx fy fz";

/// A LAMMPS text dump (`dump custom ... id type x y z vx vy vz omegax omegay omegaz
/// radius fx fy fz`) of the spheres, in id order, which OVITO reads as a file sequence.
/// Ids and types start at 1 as in LAMMPS (grains id + 1, material index + 1).
pub fn lammps_dump(w: &mut dyn Write, setup: &Setup, s: &State) -> io::Result<()> {
    let p = &s.particles;
    let d = &setup.domain;
    writeln!(
        w,
        "ITEM: TIMESTEP\n{}\nITEM: NUMBER OF ATOMS\n{}",
        s.step,
        p.len()
    )?;
    let bound = |a: usize| if d.periodic[a] { "pp" } else { "ff" };
    writeln!(w, "ITEM: BOX BOUNDS {} {} {}", bound(0), bound(1), bound(2))?;
    for a in 0..3 {
        writeln!(w, "{:e} {:e}", d.lo[a], d.hi[a])?;
    }
    writeln!(w, "ITEM: ATOMS {DUMP_COLUMNS}")?;
    let mut order: Vec<usize> = (0..p.len()).collect();
    order.sort_unstable_by_key(|&i| p.id[i]);
    for i in order {
        let (x, v, o, f) = (p.pos[i], p.vel[i], p.omega[i], p.force[i]);
        writeln!(
            w,
            "{} {} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e}",
            p.id[i] + 1,
            p.material[i] + 1,
            x.x,
            x.y,
            x.z,
            v.x,
            v.y,
            v.z,
            o.x,
            o.y,
            o.z,
            p.radius[i],
            f.x,
            f.y,
            f.z
        )?;
    }
    Ok(())
}

/// A view: the two axes shown (indices into x, y, z) and the depth axis, looked at
/// from its far end.
struct View {
    axes: [usize; 2],
    depth: usize,
    names: [&'static str; 2],
    file: &'static str,
    what: &'static str,
}

const VIEWS: [View; 2] = [
    View {
        axes: [0, 2],
        depth: 1,
        names: ["x", "z"],
        file: "particles_side.png",
        what: "from the side (along y)",
    },
    View {
        axes: [0, 1],
        depth: 2,
        names: ["x", "y"],
        file: "particles_top.png",
        what: "from above (along z)",
    },
];

/// The walls as seen in `v`, within the domain: planes seen edge-on as lines, cylinders
/// along the view as circles and across it as their two sides, spheres as circles.
fn outlines(setup: &Setup, v: &View) -> Vec<Outline> {
    let (lo, hi) = (setup.domain.lo, setup.domain.hi);
    let on = |p: DVec3| DVec2::new(p[v.axes[0]], p[v.axes[1]]);
    let circle = |c: DVec3, r: f64| Outline {
        points: (0..=128)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 128.0;
                on(c) + r * DVec2::new(a.cos(), a.sin())
            })
            .collect(),
        closed: false,
    };
    // The line through `p` along `u` (in view axes), cut to the domain's view.
    let line = |p: DVec2, u: DVec2| -> Option<Outline> {
        let (l, h) = (on(lo), on(hi));
        let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
        for a in 0..2 {
            if u[a].abs() < 1e-12 {
                if p[a] < l[a] || p[a] > h[a] {
                    return None;
                }
                continue;
            }
            let (ta, tb) = ((l[a] - p[a]) / u[a], (h[a] - p[a]) / u[a]);
            t0 = t0.max(ta.min(tb));
            t1 = t1.min(ta.max(tb));
        }
        (t0 < t1).then(|| Outline {
            points: vec![p + t0 * u, p + t1 * u],
            closed: false,
        })
    };
    let mut out = Vec::new();
    for w in &setup.walls {
        match w.shape {
            WallShape::Plane { point, normal } => {
                let n = DVec3::from(normal).normalize();
                if n[v.depth].abs() < 1e-9 {
                    let along = DVec2::new(-n[v.axes[1]], n[v.axes[0]]);
                    out.extend(line(on(DVec3::from(point)), along));
                }
            }
            WallShape::Disk {
                centre,
                normal,
                radius,
                hole,
            } => {
                let (c, n) = (DVec3::from(centre), DVec3::from(normal).normalize());
                let (e1, e2) = n.any_orthonormal_pair();
                // A circle of the plate, projected: an ellipse, or a segment edge-on.
                let ring = |r: f64| Outline {
                    points: (0..=128)
                        .map(|k| {
                            let a = std::f64::consts::TAU * k as f64 / 128.0;
                            on(c + r * (a.cos() * e1 + a.sin() * e2))
                        })
                        .collect(),
                    closed: false,
                };
                if radius.is_finite() {
                    out.push(ring(radius));
                } else if n[v.depth].abs() < 1e-9 {
                    let along = DVec2::new(-n[v.axes[1]], n[v.axes[0]]).normalize();
                    if let Some(l) = line(on(c), along) {
                        let t: Vec<f64> =
                            l.points.iter().map(|q| (*q - on(c)).dot(along)).collect();
                        for (a, b) in [(t[0], t[1].min(-hole)), (t[0].max(hole), t[1])] {
                            if a < b {
                                out.push(Outline {
                                    points: vec![on(c) + a * along, on(c) + b * along],
                                    closed: false,
                                });
                            }
                        }
                    }
                }
                // Edge-on, an unbounded plate's hole is the gap in its line.
                if hole > 0.0 && (radius.is_finite() || n[v.depth].abs() >= 1e-9) {
                    out.push(ring(hole));
                }
            }
            WallShape::Rectangle {
                centre,
                normal,
                edge,
                size,
            } => {
                let (c, n, e) = (
                    DVec3::from(centre),
                    DVec3::from(normal).normalize(),
                    DVec3::from(edge),
                );
                let e1: DVec3 = (e - e.dot(n) * n).normalize();
                let e2 = n.cross(e1);
                let corner = |a: f64, b: f64| on(c + 0.5 * (a * size[0] * e1 + b * size[1] * e2));
                out.push(Outline {
                    points: vec![
                        corner(-1.0, -1.0),
                        corner(1.0, -1.0),
                        corner(1.0, 1.0),
                        corner(-1.0, 1.0),
                    ],
                    closed: true,
                });
            }
            WallShape::Sphere { centre, radius, .. } => {
                out.push(circle(DVec3::from(centre), radius))
            }
            WallShape::Cylinder {
                point,
                axis,
                radius,
                ..
            } => {
                let u = DVec3::from(axis).normalize();
                if (u[v.depth].abs() - 1.0).abs() < 1e-9 {
                    out.push(circle(DVec3::from(point), radius));
                } else if u[v.depth].abs() < 1e-9 {
                    let along = on(u).normalize();
                    let side = DVec2::new(-along.y, along.x) * radius;
                    for s in [side, -side] {
                        out.extend(line(on(DVec3::from(point)) + s, along));
                    }
                }
            }
        }
    }
    out
}

/// Writes the history's plots and the two views of the final spheres.
pub fn write_plots(
    dir: &Path,
    h: &grains_core::history::History,
    setup: &Setup,
    s: &State,
) -> anyhow::Result<()> {
    let walls: Vec<&str> = setup.walls.iter().map(|w| w.name.as_str()).collect();
    let units = crate::dem::plots::Units {
        energy: "J",
        force: "N",
        per: "",
    };
    crate::dem::plots::history_plots(dir, h, &walls, &["x", "y", "z"], &units)?;
    let p = &s.particles;
    for v in &VIEWS {
        // The far spheres first, so the near ones are drawn over them.
        let mut order: Vec<usize> = (0..p.len()).collect();
        let toward: f64 = if v.depth == 1 { -1.0 } else { 1.0 };
        order.sort_by(|&a, &b| {
            (toward * p.pos[a][v.depth]).total_cmp(&(toward * p.pos[b][v.depth]))
        });
        let centres: Vec<DVec2> = order
            .iter()
            .map(|&i| DVec2::new(p.pos[i][v.axes[0]], p.pos[i][v.axes[1]]))
            .collect();
        let radii: Vec<f64> = order.iter().map(|&i| p.radius[i]).collect();
        let speed: Vec<f64> = order.iter().map(|&i| p.vel[i].length()).collect();
        ParticleMap {
            title: &format!(
                "Spheres at t = {} seen {}, coloured by speed",
                time_label(s.time),
                v.what
            ),
            centres: &centres,
            radii: &radii,
            values: &speed,
            value_label: "speed (m/s)",
            outlines: &outlines(setup, v),
        }
        .write_png_axes(&dir.join(v.file), v.names)?;
    }
    Ok(())
}
