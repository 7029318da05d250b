//! ParaView output of a DEM run: particle frames and the walls as VTP, indexed by a PVD.
//! A run spread over ranks writes each frame as pieces, one `.vtp` per rank of the
//! particles it owns, and rank 0 the `.pvtp` over them, which the PVD lists: no rank
//! sends its particles anywhere for a frame.

use super::ranks::Part;
use super::Dem;
use crate::frames::Framed;
use glam::DVec2;
use grains_core::atomic::write_atomic_with;
use grains_core::vtk::{DataArray, PolyData};
use grains_dem::{diagnostics, Setup, State};
use std::io::{self, Write};
use std::path::Path;

impl Framed for Dem {
    fn static_parts(&self, dir: &Path) -> io::Result<Vec<(&'static str, String)>> {
        if self.setup.walls.is_empty() {
            return Ok(Vec::new());
        }
        walls_polydata(&self.setup).write(&dir.join("walls.vtp"))?;
        Ok(vec![("walls", "walls.vtp".into())])
    }

    fn write_frame(&self, dir: &Path, k: usize) -> io::Result<Vec<(&'static str, String)>> {
        if let Some(part) = &self.ranks {
            return self.write_pieces(part, dir, k);
        }
        let name = format!("particles_{k:05}.vtp");
        particles_polydata(&self.setup, &self.state).write(&dir.join(&name))?;
        if self.lammps_dump {
            let dump = format!("particles_{k:05}.dump");
            write_atomic_with(&dir.join(dump), |w| {
                lammps_dump(w, &self.setup, &self.state)
            })?;
        }
        Ok(vec![("particles", name)])
    }
}

impl Dem {
    /// This rank's piece of frame `k` (its own particles, not its ghosts, with the
    /// serial frame's arrays), and on rank 0 the index over every rank's piece
    /// ([`crate::ranks::write_piece`]).
    fn write_pieces(
        &self,
        part: &Part,
        dir: &Path,
        k: usize,
    ) -> io::Result<Vec<(&'static str, String)>> {
        let poly = particles_polydata_of(&self.setup, &part.local, &part.own());
        let at = (part.rank(), part.ranks());
        let Some(name) = crate::ranks::write_piece(&poly, dir, k, at)? else {
            return Ok(Vec::new());
        };
        if self.lammps_dump {
            // The dump is one file of every particle: rank 0 has gathered them for it.
            let dump = format!("particles_{k:05}.dump");
            write_atomic_with(&dir.join(dump), |w| {
                lammps_dump(w, &self.setup, &self.state)
            })?;
        }
        Ok(vec![("particles", name)])
    }
}

/// The particles as VTK vertices with their fields: among them each particle's mass
/// (kg/m) and contact stress (Pa, Love's average over the disk, tension positive; a
/// 3 × 3 tensor with zero z row and column, as ParaView expects), which the dispersal
/// analysis of a finished run reads back.
pub fn particles_polydata(setup: &Setup, s: &State) -> PolyData {
    let all: Vec<usize> = (0..s.particles.len()).collect();
    particles_polydata_of(setup, s, &all)
}

/// [`particles_polydata`] of the particles `keep` (indices into `s`, in that order);
/// their contacts and stress count every listed partner, ghosts included.
pub fn particles_polydata_of(setup: &Setup, s: &State, keep: &[usize]) -> PolyData {
    let p = &s.particles;
    let of = |v: &[DVec2]| -> Vec<DVec2> { keep.iter().map(|&i| v[i]).collect() };
    let each = |f: &dyn Fn(usize) -> f64| -> Vec<f64> { keep.iter().map(|&i| f(i)).collect() };
    let mut poly = PolyData::from_points_2d(&of(&p.pos));
    let contacts = diagnostics::contact_counts(setup, s);
    let stress = grains_dem::stress::particle_stress(setup, s);
    let stress: Vec<glam::DMat2> = keep.iter().map(|&i| stress[i]).collect();
    poly.point_data = vec![
        DataArray::scalar_i64("id", keep.iter().map(|&i| p.id[i] as i64).collect()),
        DataArray::scalar_f64("radius", each(&|i| p.radius[i])),
        DataArray::scalar_f64("mass", each(&|i| p.mass(i))),
        DataArray::vector2_f64("velocity", &of(&p.vel)),
        DataArray::scalar_f64("speed", each(&|i| p.vel[i].length())),
        DataArray::scalar_f64("omega", each(&|i| p.omega[i])),
        DataArray::vector2_f64("force", &of(&p.force)),
        DataArray::scalar_i32(
            "contacts",
            keep.iter().map(|&i| contacts[i] as i32).collect(),
        ),
        DataArray::scalar_i32(
            "material",
            keep.iter().map(|&i| p.material[i] as i32).collect(),
        ),
        stress_array(STRESS_ARRAY, &stress),
    ];
    poly
}

/// Name of the particles' contact stress in frames.
pub const STRESS_ARRAY: &str = "stress";

/// 2 × 2 tensors as a 9-component VTK array (row-major, z row and column zero).
pub fn stress_array(name: &str, t: &[glam::DMat2]) -> DataArray {
    let mut v = Vec::with_capacity(9 * t.len());
    for m in t {
        let (xx, xy, yx, yy) = (m.x_axis.x, m.y_axis.x, m.x_axis.y, m.y_axis.y);
        v.extend_from_slice(&[xx, xy, 0.0, yx, yy, 0.0, 0.0, 0.0, 0.0]);
    }
    DataArray::new(name, 9, grains_core::vtk::ArrayData::F64(v))
}

/// A LAMMPS text dump (`dump custom ... id type x y z radius vx vy vz omegaz fx fy fz`)
/// of the particles, which OVITO reads as a file sequence. Ids and types start at 1 as in
/// LAMMPS (grains id + 1, material index + 1).
pub fn lammps_dump(w: &mut dyn Write, setup: &Setup, s: &State) -> io::Result<()> {
    let p = &s.particles;
    let d = &setup.domain;
    let bound = |periodic: bool| if periodic { "pp" } else { "ff" };
    let rmax = p.max_radius().max(f64::MIN_POSITIVE);
    writeln!(
        w,
        "ITEM: TIMESTEP\n{}\nITEM: NUMBER OF ATOMS\n{}",
        s.step,
        p.len()
    )?;
    writeln!(
        w,
        "ITEM: BOX BOUNDS {} {} pp",
        bound(d.periodic[0]),
        bound(d.periodic[1])
    )?;
    writeln!(
        w,
        "{:e} {:e}\n{:e} {:e}\n{:e} {:e}",
        d.lo.x, d.hi.x, d.lo.y, d.hi.y, -rmax, rmax
    )?;
    writeln!(
        w,
        "ITEM: ATOMS id type x y z radius vx vy vz omegaz fx fy fz"
    )?;
    let mut order: Vec<usize> = (0..p.len()).collect();
    order.sort_unstable_by_key(|&i| p.id[i]);
    for i in order {
        writeln!(
            w,
            "{} {} {:e} {:e} 0 {:e} {:e} {:e} 0 {:e} {:e} {:e} 0",
            p.id[i] + 1,
            p.material[i] + 1,
            p.pos[i].x,
            p.pos[i].y,
            p.radius[i],
            p.vel[i].x,
            p.vel[i].y,
            p.omega[i],
            p.force[i].x,
            p.force[i].y
        )?;
    }
    Ok(())
}

/// The walls as poly-lines, with the wall index as cell data.
pub fn walls_polydata(setup: &Setup) -> PolyData {
    let mut points = Vec::new();
    let mut lines = Vec::new();
    for wall in &setup.walls {
        let start = points.len() as i64;
        let outline = wall.shape.outline();
        points.extend(outline.iter().map(|q| [q.x, q.y, 0.0]));
        lines.push((start..start + outline.len() as i64).collect());
    }
    PolyData {
        points,
        verts: Vec::new(),
        lines,
        point_data: Vec::new(),
        cell_data: vec![DataArray::scalar_i32(
            "wall",
            (0..setup.walls.len() as i32).collect(),
        )],
    }
}
