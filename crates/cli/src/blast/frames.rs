//! ParaView output of a blast run: the charge's mesh as VTU (pressure, density, burn
//! fraction, energy, velocity) and the particles as VTP, grouped per time in one PVD.

use grains_core::pvd::PvdSeries;
use grains_core::vtk::{cell_type, DataArray, UnstructuredGrid};
use grains_dem::{Setup, State};
use grains_fem::Charge;
use std::io;
use std::path::{Path, PathBuf};

/// Writes numbered frames into `frames/` and keeps `frames/series.pvd` current.
pub struct FrameWriter {
    dir: PathBuf,
    series: PvdSeries,
    count: usize,
}

impl FrameWriter {
    /// Creates (and empties) the frames directory.
    pub fn create(out: &Path) -> io::Result<Self> {
        let dir = out.join("frames");
        if dir.exists() {
            std::fs::remove_dir_all(&dir)?;
        }
        std::fs::create_dir_all(&dir)?;
        Ok(FrameWriter {
            series: PvdSeries::new(&dir.join("series.pvd")),
            dir,
            count: 0,
        })
    }

    /// Frames written.
    pub fn count(&self) -> usize {
        self.count
    }

    /// Writes the charge (and the particles, if any) at time `t`.
    pub fn write(
        &mut self,
        t: f64,
        charge: &Charge,
        particles: Option<(&Setup, &State)>,
    ) -> io::Result<()> {
        let mesh_name = format!("charge_{:05}.vtu", self.count);
        charge_grid(charge).write(&self.dir.join(&mesh_name))?;
        match particles {
            Some((setup, state)) => {
                let pname = format!("particles_{:05}.vtp", self.count);
                crate::dem::frames::particles_polydata(setup, state)
                    .write(&self.dir.join(&pname))?;
                self.series
                    .push_group(t, &[("charge", &mesh_name), ("particles", &pname)])?;
            }
            None => self.series.push(t, &mesh_name)?,
        }
        self.count += 1;
        Ok(())
    }
}

/// The charge's triangles with their state as cell data and node velocities.
pub fn charge_grid(c: &Charge) -> UnstructuredGrid {
    let mut g = UnstructuredGrid {
        points: c.nodes.pos.iter().map(|p| [p.x, p.y, 0.0]).collect(),
        ..Default::default()
    };
    for t in &c.elems.tri {
        g.push_cell(
            cell_type::TRIANGLE,
            &[t[0] as i64, t[1] as i64, t[2] as i64],
        );
    }
    let el = &c.elems;
    let density: Vec<f64> = el.mass.iter().zip(&el.area).map(|(m, a)| m / a).collect();
    g.cell_data = vec![
        DataArray::scalar_f64("pressure", el.pressure.clone()),
        DataArray::scalar_f64("density", density),
        DataArray::scalar_f64("burn_fraction", el.lambda.clone()),
        DataArray::scalar_f64("specific_energy", el.energy.clone()),
        DataArray::scalar_f64("viscosity", el.q.clone()),
        DataArray::scalar_f64("sound_speed", el.sound.clone()),
    ];
    g.point_data = vec![DataArray::vector2_f64("velocity", &c.nodes.vel)];
    g
}
