//! ParaView output of a DEM run: particle frames and the walls as VTP, indexed by a PVD.

use grains_core::atomic::write_atomic_with;
use grains_core::pvd::PvdSeries;
use grains_core::vtk::{DataArray, PolyData};
use grains_dem::{diagnostics, Setup, State};
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// Writes numbered particle frames into `frames/` and keeps `frames/series.pvd` current;
/// optionally also a LAMMPS-style text dump of each frame for OVITO users.
pub struct FrameWriter {
    dir: PathBuf,
    series: PvdSeries,
    count: usize,
    walls: bool,
    dump: bool,
}

impl FrameWriter {
    /// Creates (and empties) the frames directory and writes the static walls file.
    pub fn create(out: &Path, setup: &Setup, dump: bool) -> io::Result<Self> {
        let dir = out.join("frames");
        if dir.exists() {
            std::fs::remove_dir_all(&dir)?;
        }
        std::fs::create_dir_all(&dir)?;
        let walls = !setup.walls.is_empty();
        if walls {
            walls_polydata(setup).write(&dir.join("walls.vtp"))?;
        }
        Ok(FrameWriter {
            series: PvdSeries::new(&dir.join("series.pvd")),
            dir,
            count: 0,
            walls,
            dump,
        })
    }

    /// Reopens the frames of a run continued from a checkpoint at `time`, which had
    /// written `count` frames by then: later entries of the series are dropped.
    pub fn resume(
        out: &Path,
        setup: &Setup,
        time: f64,
        count: usize,
        dump: bool,
    ) -> io::Result<Self> {
        let dir = out.join("frames");
        let mut series = PvdSeries::load(&dir.join("series.pvd"))?;
        series.truncate_after(time)?;
        Ok(FrameWriter {
            series,
            dir,
            count,
            walls: !setup.walls.is_empty(),
            dump,
        })
    }

    /// Number of frames written.
    pub fn count(&self) -> usize {
        self.count
    }

    /// Writes one frame of the particles at the state's time.
    pub fn write(&mut self, setup: &Setup, s: &State) -> io::Result<()> {
        let name = format!("particles_{:05}.vtp", self.count);
        particles_polydata(setup, s).write(&self.dir.join(&name))?;
        if self.dump {
            let dump = format!("particles_{:05}.dump", self.count);
            write_atomic_with(&self.dir.join(dump), |w| lammps_dump(w, setup, s))?;
        }
        if self.walls {
            self.series
                .push_group(s.time, &[("particles", &name), ("walls", "walls.vtp")])?;
        } else {
            self.series.push(s.time, &name)?;
        }
        self.count += 1;
        Ok(())
    }
}

/// The particles as VTK vertices with their fields.
pub fn particles_polydata(setup: &Setup, s: &State) -> PolyData {
    let p = &s.particles;
    let mut poly = PolyData::from_points_2d(&p.pos);
    let contacts = diagnostics::contact_counts(setup, s);
    poly.point_data = vec![
        DataArray::scalar_i64("id", p.id.iter().map(|&k| k as i64).collect()),
        DataArray::scalar_f64("radius", p.radius.clone()),
        DataArray::vector2_f64("velocity", &p.vel),
        DataArray::scalar_f64("speed", p.vel.iter().map(|v| v.length()).collect()),
        DataArray::scalar_f64("omega", p.omega.clone()),
        DataArray::vector2_f64("force", &p.force),
        DataArray::scalar_i32("contacts", contacts.iter().map(|&c| c as i32).collect()),
        DataArray::scalar_i32("material", p.material.iter().map(|&m| m as i32).collect()),
    ];
    poly
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
