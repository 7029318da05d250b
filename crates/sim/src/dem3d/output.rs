//! What a 3D run writes besides its history: ParaView frames of the spheres (3D points,
//! vector velocity, ω and force, the 3 × 3 contact stress), optionally a LAMMPS dump
//! beside each frame, and the plots: the history's
//! (as in 2D) and the final spheres seen from the side and from above, the views chosen
//! by gravity ([`views`]), with the walls drawn as the view sees them.

use super::Dem3;
use crate::frames::Framed;
use glam::{DVec2, DVec3};
use grains_core::atomic::write_atomic_with;
use grains_core::plot::{time_label, Outline, ParticleMap};
use grains_core::vtk::{ArrayData, DataArray, PolyData};
use grains_dem3d::{diagnostics, Setup, State, Wall, WallShape};
use std::io::{self, Write};
use std::path::Path;

fn flat(v: &[DVec3]) -> Vec<f64> {
    v.iter().flat_map(|x| x.to_array()).collect()
}

/// The spheres as VTK vertices with their fields.
pub fn particles_polydata(setup: &Setup, s: &State) -> PolyData {
    let all: Vec<usize> = (0..s.particles.len()).collect();
    particles_polydata_of(setup, s, &all)
}

/// [`particles_polydata`] of the spheres `keep` (indices into `s`, in that order);
/// their contacts and stress count every listed partner, ghosts included.
pub fn particles_polydata_of(setup: &Setup, s: &State, keep: &[usize]) -> PolyData {
    let p = &s.particles;
    let stress = grains_dem3d::stress::particle_stress(setup, s);
    let contacts = diagnostics::contact_counts(setup, s);
    let of = |v: &[DVec3]| -> Vec<f64> { flat(&keep.iter().map(|&i| v[i]).collect::<Vec<_>>()) };
    let each = |f: &dyn Fn(usize) -> f64| -> Vec<f64> { keep.iter().map(|&i| f(i)).collect() };
    let int = |f: &dyn Fn(usize) -> i32| -> Vec<i32> { keep.iter().map(|&i| f(i)).collect() };
    PolyData {
        points: keep.iter().map(|&i| p.pos[i].to_array()).collect(),
        verts: (0..keep.len() as i64).map(|i| vec![i]).collect(),
        point_data: vec![
            DataArray::scalar_i64("id", keep.iter().map(|&i| p.id[i] as i64).collect()),
            DataArray::scalar_f64("radius", each(&|i| p.radius[i])),
            DataArray::scalar_f64("mass", each(&|i| p.mass(i))),
            DataArray::vector3_f64("velocity", of(&p.vel)),
            DataArray::scalar_f64("speed", each(&|i| p.vel[i].length())),
            DataArray::vector3_f64("omega", of(&p.omega)),
            DataArray::vector3_f64("force", of(&p.force)),
            DataArray::scalar_i32("contacts", int(&|i| contacts[i] as i32)),
            DataArray::scalar_i32("material", int(&|i| p.material[i] as i32)),
            // Row-major 3 × 3, as ParaView reads a 9-component array.
            DataArray::new(
                crate::dem::frames::STRESS_ARRAY,
                9,
                ArrayData::F64(
                    keep.iter()
                        .flat_map(|&i| stress[i].transpose().to_cols_array())
                        .collect(),
                ),
            ),
        ],
        ..PolyData::default()
    }
}

impl Framed for Dem3 {
    fn write_frame(&self, dir: &Path, k: usize) -> io::Result<Vec<(&'static str, String)>> {
        let name = match &self.ranks {
            Some(part) => {
                // This rank's piece (its own spheres); rank 0 also the index over all.
                let poly = particles_polydata_of(&self.setup, &part.local, &part.own());
                let at = (part.rank(), part.ranks());
                match crate::ranks::write_piece(&poly, dir, k, at)? {
                    Some(index) => index,
                    None => return Ok(Vec::new()),
                }
            }
            None => {
                let name = format!("particles_{k:05}.vtp");
                particles_polydata(&self.setup, &self.state).write(&dir.join(&name))?;
                name
            }
        };
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

/// A view: the screen's right (`e1`) and up (`e2`) directions and `toward`, e1 × e2,
/// pointing at the viewer; each axis named by the coordinate it runs along, if any.
struct View {
    e1: DVec3,
    e2: DVec3,
    toward: DVec3,
    names: [String; 2],
    file: &'static str,
    what: String,
}

/// What views of spheres are drawn in: the box whose corners bound the lines drawn
/// (the domain), gravity (which way is up) and the walls.
pub struct Scene<'a> {
    /// Lower corner (m).
    pub lo: DVec3,
    /// Upper corner (m).
    pub hi: DVec3,
    /// Gravity (m/s²); zero is taken as along −z.
    pub gravity: DVec3,
    /// The walls drawn.
    pub walls: &'a [Wall],
}

impl<'a> Scene<'a> {
    /// A run's scene: its domain, gravity and walls.
    pub fn of(setup: &'a Setup) -> Self {
        Scene {
            lo: setup.domain.lo,
            hi: setup.domain.hi,
            gravity: setup.gravity,
            walls: &setup.walls,
        }
    }
}

/// Spheres coloured by one value each, as [`write_views`] draws them.
pub struct Coloured<'a> {
    /// Centres (m).
    pub pos: &'a [DVec3],
    /// Radii (m).
    pub radius: &'a [f64],
    /// The value each sphere is coloured by.
    pub values: &'a [f64],
    /// The values' name and unit, for the colour bar ("speed (m/s)").
    pub label: &'a str,
    /// What the values are, for the title ("speed").
    pub by: &'a str,
}

/// A direction's name: a coordinate axis (signed), or `other` when it is none.
fn axis_name(u: DVec3, other: &str) -> String {
    for (a, name) in ["x", "y", "z"].iter().enumerate() {
        if (u[a].abs() - 1.0).abs() < 1e-9 {
            return if u[a] > 0.0 {
                name.to_string()
            } else {
                format!("−{name}")
            };
        }
    }
    other.to_string()
}

/// The side and top views of a run under `gravity`: the top looks down along gravity,
/// the side is a vertical plane (gravity pointing down the screen) seen along a turning
/// cylinder's axis where one lies across gravity (a drum is seen end-on, as a circle),
/// else along a coordinate axis across gravity (y when gravity is along −z).
fn views(scene: &Scene) -> [View; 2] {
    let g = scene.gravity;
    let up = if g == DVec3::ZERO {
        DVec3::Z
    } else {
        -g.normalize()
    };
    let across = |u: DVec3| u.dot(up).abs() < 1e-9;
    let drum = scene.walls.iter().find_map(|w| match w.shape {
        WallShape::Cylinder { axis, .. } => {
            let a = DVec3::from(axis).normalize();
            across(a).then_some(a)
        }
        _ => None,
    });
    let right = match drum {
        // Seen along the axis, either way: the one that puts the larger coordinate right.
        Some(a) => {
            let e = up.cross(a);
            if e.x + e.y + e.z < 0.0 {
                -e
            } else {
                e
            }
        }
        None => [DVec3::X, DVec3::Y, DVec3::Z]
            .into_iter()
            .find(|&u| across(u))
            .unwrap_or_else(|| up.any_orthonormal_vector()),
    };
    let side_toward = right.cross(up);
    // On top, the side view's right stays right.
    let top_e2 = up.cross(right);
    let (r, u) = (axis_name(right, "s"), axis_name(up, "height"));
    [
        View {
            e1: right,
            e2: up,
            toward: side_toward,
            names: [r.clone(), u.clone()],
            file: "side",
            what: format!(
                "from the side (along {}; gravity down)",
                axis_name(-side_toward, "the view")
            ),
        },
        View {
            e1: right,
            e2: top_e2,
            toward: up,
            names: [r, axis_name(top_e2, "t")],
            file: "top",
            what: format!("from above (along gravity, {})", axis_name(-up, "g")),
        },
    ]
}

/// The walls as seen in `v`, within the scene's box: planes seen edge-on as lines,
/// cylinders along the view as circles and across it as their two sides, spheres as
/// circles.
fn outlines(scene: &Scene, v: &View) -> Vec<Outline> {
    let (lo, hi) = (scene.lo, scene.hi);
    // The domain's corners in the view: the box lines are cut to.
    let frame = (0..8).fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(l, h), k| {
            let c = DVec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            );
            let q = DVec2::new(c.dot(v.e1), c.dot(v.e2));
            (l.min(q), h.max(q))
        },
    );
    let on = |p: DVec3| DVec2::new(p.dot(v.e1), p.dot(v.e2));
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
        let (l, h) = (frame.0, frame.1);
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
    for w in scene.walls {
        match w.shape {
            WallShape::Plane { point, normal } => {
                let n = DVec3::from(normal).normalize();
                if n.dot(v.toward).abs() < 1e-9 {
                    let along = DVec2::new(-n.dot(v.e2), n.dot(v.e1));
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
                } else if n.dot(v.toward).abs() < 1e-9 {
                    let along = DVec2::new(-n.dot(v.e2), n.dot(v.e1)).normalize();
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
                if hole > 0.0 && (radius.is_finite() || n.dot(v.toward).abs() >= 1e-9) {
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
                // A released wall (infinite radius) is gone: nothing to draw.
                if !radius.is_finite() {
                    continue;
                }
                if (u.dot(v.toward).abs() - 1.0).abs() < 1e-9 {
                    out.push(circle(DVec3::from(point), radius));
                } else if u.dot(v.toward).abs() < 1e-9 {
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
    let speed: Vec<f64> = p.vel.iter().map(|v| v.length()).collect();
    let spheres = Coloured {
        pos: &p.pos,
        radius: &p.radius,
        values: &speed,
        label: "speed (m/s)",
        by: "speed",
    };
    let title = format!("Spheres at t = {}", time_label(s.time));
    write_views(dir, &Scene::of(setup), &spheres, &title, "particles")
}

/// Writes `spheres` seen from the side and from above ([`views`]) with the scene's
/// walls, as `{stem}_side.png` and `{stem}_top.png` in `dir`; `title` begins each
/// plot's title ("Spheres at t = 1 s").
pub fn write_views(
    dir: &Path,
    scene: &Scene,
    spheres: &Coloured,
    title: &str,
    stem: &str,
) -> anyhow::Result<()> {
    for v in &views(scene) {
        // The far spheres first, so the near ones are drawn over them.
        let pos = spheres.pos;
        let mut order: Vec<usize> = (0..pos.len()).collect();
        order.sort_by(|&a, &b| pos[a].dot(v.toward).total_cmp(&pos[b].dot(v.toward)));
        let centres: Vec<DVec2> = order
            .iter()
            .map(|&i| DVec2::new(pos[i].dot(v.e1), pos[i].dot(v.e2)))
            .collect();
        let radii: Vec<f64> = order.iter().map(|&i| spheres.radius[i]).collect();
        let values: Vec<f64> = order.iter().map(|&i| spheres.values[i]).collect();
        ParticleMap {
            title: &format!("{title} seen {}, coloured by {}", v.what, spheres.by),
            centres: &centres,
            radii: &radii,
            values: &values,
            value_label: spheres.label,
            outlines: &outlines(scene, v),
        }
        .write_png_axes(
            &dir.join(format!("{stem}_{}.png", v.file)),
            [&v.names[0], &v.names[1]],
        )?;
    }
    Ok(())
}
