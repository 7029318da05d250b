//! The `[[wall]]`s of a 3D scenario, checked and built into the engine's walls: planes,
//! boxes, flat rings (a plate, a silo's floor with its orifice), rectangles, cylinders
//! and spheres, each at rest or moving as prescribed.

use super::assemble::{finite3, material_index, AXES};
use super::scenario::{Scenario, WallSpec};
use glam::DVec3;
use grains_core::input::{non_negative, positive, InputError};
use grains_dem3d::walls::Motion;
use grains_dem3d::{Wall, WallShape};

/// The scenario's walls, in order (a box gives six), or the first bad value.
pub fn walls(s: &Scenario) -> Result<Vec<Wall>, InputError> {
    let mut out: Vec<Wall> = Vec::new();
    for (w, spec) in s.walls.iter().enumerate() {
        let key = format!("wall[{w}]");
        let k = |f: &str| format!("{key}.{f}");
        let (name, material) = match spec {
            WallSpec::Plane { name, material, .. }
            | WallSpec::Disk { name, material, .. }
            | WallSpec::Rectangle { name, material, .. }
            | WallSpec::Box { name, material, .. }
            | WallSpec::Cylinder { name, material, .. }
            | WallSpec::Sphere { name, material, .. } => (name, material),
        };
        let material = match material {
            Some(m) => Some(material_index(s, &k("material"), m)?),
            None => None,
        };
        let nonzero = |f: &str, v: [f64; 3]| -> Result<DVec3, InputError> {
            let d = finite3(&k(f), v)?;
            if d == DVec3::ZERO {
                return Err(InputError::new(k(f), format!("{v:?}"), "must not be zero"));
            }
            Ok(d)
        };
        let mut shapes: Vec<(String, WallShape)> = Vec::new();
        let mut moving = (None, None);
        match *spec {
            WallSpec::Plane {
                point,
                normal,
                velocity,
                omega,
                ..
            } => {
                finite3(&k("point"), point)?;
                nonzero("normal", normal)?;
                shapes.push((name.clone(), WallShape::Plane { point, normal }));
                moving = (velocity, omega);
            }
            WallSpec::Disk {
                centre,
                normal,
                radius,
                hole,
                velocity,
                omega,
                ..
            } => {
                finite3(&k("centre"), centre)?;
                nonzero("normal", normal)?;
                let radius = match radius {
                    Some(r) => {
                        positive(&k("radius"), r)?;
                        r
                    }
                    None => f64::INFINITY,
                };
                let hole = hole.unwrap_or(0.0);
                non_negative(&k("hole"), hole)?;
                if hole >= radius {
                    return Err(InputError::new(
                        k("hole"),
                        hole,
                        format!("must be less than radius = {radius}"),
                    ));
                }
                shapes.push((
                    name.clone(),
                    WallShape::Disk {
                        centre,
                        normal,
                        radius,
                        hole,
                    },
                ));
                moving = (velocity, omega);
            }
            WallSpec::Rectangle {
                centre,
                normal,
                edge,
                size,
                velocity,
                ..
            } => {
                finite3(&k("centre"), centre)?;
                let u = nonzero("normal", normal)?.normalize();
                let e = nonzero("edge", edge)?;
                if (e - e.dot(u) * u).length() <= 1e-9 * e.length() {
                    return Err(InputError::new(
                        k("edge"),
                        format!("{edge:?}"),
                        "must not be parallel to the normal",
                    ));
                }
                positive(&k("size[0]"), size[0])?;
                positive(&k("size[1]"), size[1])?;
                shapes.push((
                    name.clone(),
                    WallShape::Rectangle {
                        centre,
                        normal,
                        edge,
                        size,
                    },
                ));
                moving = (velocity, None);
            }
            WallSpec::Box { lo, hi, .. } => {
                let (l, h) = (finite3(&k("lo"), lo)?, finite3(&k("hi"), hi)?);
                if !l.cmplt(h).all() {
                    return Err(InputError::new(
                        k("hi"),
                        format!("{hi:?}"),
                        format!("must exceed lo = {lo:?} on every axis"),
                    ));
                }
                for a in 0..3 {
                    let mut normal = [0.0; 3];
                    normal[a] = 1.0;
                    for (end, point) in [("lo", lo), ("hi", hi)] {
                        shapes.push((
                            format!("{name}_{}{end}", AXES[a]),
                            WallShape::Plane { point, normal },
                        ));
                    }
                }
            }
            WallSpec::Cylinder {
                point,
                axis,
                radius,
                inside,
                velocity,
                omega,
                release,
                ..
            } => {
                finite3(&k("point"), point)?;
                nonzero("axis", axis)?;
                positive(&k("radius"), radius)?;
                if let Some(t) = release {
                    non_negative(&k("release"), t)?;
                }
                shapes.push((
                    name.clone(),
                    WallShape::Cylinder {
                        point,
                        axis,
                        radius,
                        inside,
                    },
                ));
                moving = (velocity, omega);
            }
            WallSpec::Sphere {
                centre,
                radius,
                inside,
                ..
            } => {
                finite3(&k("centre"), centre)?;
                positive(&k("radius"), radius)?;
                shapes.push((
                    name.clone(),
                    WallShape::Sphere {
                        centre,
                        radius,
                        inside,
                    },
                ));
            }
        }
        let motion = motion(&k, &shapes, moving)?;
        for (name, shape) in shapes {
            if out.iter().any(|o| o.name == name) {
                return Err(InputError::new(
                    k("name"),
                    format!("\"{name}\""),
                    "wall names must be unique",
                ));
            }
            out.push(Wall {
                name,
                shape,
                material,
                motion,
            });
        }
    }
    Ok(out)
}

/// The motion of a wall, checked: finite, and a spin only about the wall's own axis
/// (any other would change the wall's shape, which the engine does not follow).
fn motion(
    k: &dyn Fn(&str) -> String,
    shapes: &[(String, WallShape)],
    (velocity, omega): (Option<[f64; 3]>, Option<[f64; 3]>),
) -> Result<Motion, InputError> {
    let mut m = Motion::default();
    if let Some(v) = velocity {
        m.velocity = finite3(&k("velocity"), v)?;
    }
    if let Some(w) = omega {
        m.omega = finite3(&k("omega"), w)?;
        let axis = shapes
            .first()
            .and_then(|(_, s)| s.axis())
            .unwrap_or(DVec3::ZERO);
        if m.omega.cross(axis).length() > 1e-9 * m.omega.length() {
            return Err(InputError::new(
                k("omega"),
                format!("{w:?}"),
                format!(
                    "must be parallel to the wall's axis {:?} (a wall turns about its own axis)",
                    axis.to_array()
                ),
            ));
        }
    }
    Ok(m)
}

/// The unit axis of each turning wall, in wall order (its torque about it is recorded
/// as `<name>_torque_axis`); None for the others.
pub fn spin_axes(walls: &[Wall]) -> Vec<Option<DVec3>> {
    walls
        .iter()
        .map(|w| (w.motion.omega != DVec3::ZERO).then(|| w.motion.omega.normalize()))
        .collect()
}

/// The walls the scenario takes away and when: (index among `walls`, release time).
pub fn releases(s: &Scenario, walls: &[Wall]) -> Vec<(usize, f64)> {
    s.walls
        .iter()
        .filter_map(|spec| match spec {
            WallSpec::Cylinder {
                name,
                release: Some(t),
                ..
            } => walls.iter().position(|w| &w.name == name).map(|w| (w, *t)),
            _ => None,
        })
        .collect()
}

/// Takes away each wall of `releases` whose time has come by `time`. A released cylinder
/// gets an infinite radius, so it touches nothing: the engine's walls stay as they are
/// (their count, names, history columns and checkpointed poses), and the test depends on
/// the time alone, so a resumed run releases on the same step as the straight one.
pub fn release(walls: &mut [Wall], releases: &[(usize, f64)], time: f64) {
    for &(w, at) in releases {
        if time >= at {
            if let WallShape::Cylinder { radius, .. } = &mut walls[w].shape {
                *radius = f64::INFINITY;
            }
        }
    }
}
