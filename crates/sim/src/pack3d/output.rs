//! What `grains pack` writes for spheres besides packing.txt and summary.json: a
//! ParaView frame of the spheres (`frames/packing.vtp`: radius, contacts, rattler and
//! interior flags), the packing seen from the side and from above with its container
//! drawn (`plots/packing_side.png`, `packing_top.png`, coloured by each sphere's
//! contacts, the run's views: [`crate::dem3d::output::write_views`]), and the
//! distribution of contacts per sphere (`plots/contacts.png` and its CSV).

use crate::dem3d::output::{write_views, Coloured, Scene};
use anyhow::Context;
use glam::DVec3;
use grains_core::plot::{LinePlot, Series};
use grains_core::vtk::{DataArray, PolyData};
use grains_dem3d::{Wall, WallShape};
use grains_pack::spheres::{Container, SpherePacking};
use std::path::Path;

/// Writes the frame and the plots of `p` into `out` (`frames/`, `plots/`).
pub fn write_outputs(out: &Path, p: &SpherePacking) -> anyhow::Result<()> {
    let (plots, frames) = (out.join("plots"), out.join("frames"));
    for dir in [&plots, &frames] {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    frame(p).write(&frames.join("packing.vtp"))?;

    let (lo, hi, walls) = container_walls(p.container);
    let scene = Scene {
        lo,
        hi,
        gravity: DVec3::NEG_Z,
        walls: &walls,
    };
    let contacts: Vec<f64> = p.contacts.iter().map(|&c| c as f64).collect();
    let spheres = Coloured {
        pos: &p.pos,
        radius: &p.radius,
        values: &contacts,
        label: "contacts (spheres and walls)",
        by: "contacts",
    };
    let title = format!("{} jammed spheres", p.pos.len());
    write_views(&plots, &scene, &spheres, &title, "packing")?;

    let (z, all) = distribution(p.contacts.iter().copied());
    let (zi, inner) = distribution(
        (0..p.pos.len())
            .filter(|&i| p.interior[i] && !p.rattler[i])
            .map(|i| p.contacts[i]),
    );
    LinePlot {
        title: &format!(
            "Contacts per sphere (mean {:.3} without the {} rattlers)",
            p.coordination, p.rattlers
        ),
        x_label: "contacts per sphere z (spheres and walls)",
        y_label: "fraction of spheres, P(z)",
        series: vec![
            Series {
                name: "all spheres",
                x: &z,
                y: &all,
            },
            Series {
                name: "interior without rattlers",
                x: &zi,
                y: &inner,
            },
        ],
        log_y: false,
        points: true,
    }
    .write_png_and_csv(&plots.join("contacts.png"))?;
    Ok(())
}

/// The spheres as VTK vertices: id (their order in packing.txt), radius, contacts and
/// the rattler and interior flags.
fn frame(p: &SpherePacking) -> PolyData {
    let n = p.pos.len();
    PolyData {
        points: p.pos.iter().map(|x| x.to_array()).collect(),
        verts: (0..n as i64).map(|i| vec![i]).collect(),
        point_data: vec![
            DataArray::scalar_i64("id", (0..n as i64).collect()),
            DataArray::scalar_f64("radius", p.radius.clone()),
            DataArray::scalar_i32("contacts", p.contacts.iter().map(|&c| c as i32).collect()),
            DataArray::scalar_u8("rattler", p.rattler.iter().map(|&b| b as u8).collect()),
            DataArray::scalar_u8("interior", p.interior.iter().map(|&b| b as u8).collect()),
        ],
        ..PolyData::default()
    }
}

/// The container's bounding box and its walls as a 3D run would build them: six planes
/// for a box on `[0, size]`, a z-cylinder about the origin between the planes z = 0 and
/// z = height.
fn container_walls(c: Container) -> (DVec3, DVec3, Vec<Wall>) {
    let plane = |name: &str, point: DVec3, normal: DVec3| {
        Wall::fixed(
            name,
            WallShape::Plane {
                point: point.to_array(),
                normal: normal.to_array(),
            },
            None,
        )
    };
    match c {
        Container::Box { size } => {
            let hi = DVec3::from(size);
            let mut walls = Vec::new();
            for (a, e) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().enumerate() {
                let axis = ["x", "y", "z"][a];
                walls.push(plane(&format!("{axis}_lo"), DVec3::ZERO, e));
                walls.push(plane(&format!("{axis}_hi"), hi, e));
            }
            (DVec3::ZERO, hi, walls)
        }
        Container::Cylinder { radius, height } => {
            let hi = DVec3::new(radius, radius, height);
            let side = Wall::fixed(
                "side",
                WallShape::Cylinder {
                    point: [0.0; 3],
                    axis: [0.0, 0.0, 1.0],
                    radius,
                    inside: true,
                },
                None,
            );
            let walls = vec![
                side,
                plane("floor", DVec3::ZERO, DVec3::Z),
                plane("lid", hi, DVec3::Z),
            ];
            (DVec3::new(-radius, -radius, 0.0), hi, walls)
        }
    }
}

/// The fraction of `counts` at each value from 0 to the largest.
fn distribution(counts: impl Iterator<Item = u32>) -> (Vec<f64>, Vec<f64>) {
    let mut bins: Vec<usize> = Vec::new();
    for c in counts {
        let c = c as usize;
        if bins.len() <= c {
            bins.resize(c + 1, 0);
        }
        bins[c] += 1;
    }
    let total = bins.iter().sum::<usize>().max(1) as f64;
    (
        (0..bins.len()).map(|z| z as f64).collect(),
        bins.iter().map(|&b| b as f64 / total).collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_distribution_sums_to_one_over_every_count_up_to_the_largest() {
        let (z, p) = distribution([4u32, 6, 6, 0, 6].into_iter());
        assert_eq!(z, vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        assert_eq!(p, vec![0.2, 0.0, 0.0, 0.0, 0.2, 0.0, 0.6]);
    }

    #[test]
    fn a_box_has_six_planes_on_its_faces_and_a_cylinder_a_side_a_floor_and_a_lid() {
        let (lo, hi, walls) = container_walls(Container::Box {
            size: [1.0, 2.0, 3.0],
        });
        assert_eq!((lo, hi), (DVec3::ZERO, DVec3::new(1.0, 2.0, 3.0)));
        assert_eq!(walls.len(), 6);
        let (lo, hi, walls) = container_walls(Container::Cylinder {
            radius: 0.5,
            height: 2.0,
        });
        assert_eq!(
            (lo, hi),
            (DVec3::new(-0.5, -0.5, 0.0), DVec3::new(0.5, 0.5, 2.0))
        );
        let names: Vec<&str> = walls.iter().map(|w| w.name.as_str()).collect();
        assert_eq!(names, ["side", "floor", "lid"]);
    }
}
