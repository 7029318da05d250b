//! ParaView output of a blast run: the charge's mesh as VTU (pressure, density, burn
//! fraction, energy, velocity) and the particles as VTP, grouped per time in one PVD.

use super::Blast;
use crate::dem::frames::{particles_polydata, particles_polydata_of};
use crate::frames::Framed;
use grains_core::vtk::{cell_type, DataArray, UnstructuredGrid};
use grains_fem::Charge;
use std::io;
use std::path::Path;

impl Framed for Blast {
    fn write_frame(&self, dir: &Path, k: usize) -> io::Result<Vec<(&'static str, String)>> {
        let leader = self.ranks.as_ref().is_none_or(|rp| rp.part.rank() == 0);
        let mut parts = Vec::new();
        if leader {
            // The charge is the same on every rank: written once.
            let mesh = format!("charge_{k:05}.vtu");
            charge_grid(&self.charge).write(&dir.join(&mesh))?;
            parts.push(("charge", mesh));
        }
        if let Some(rp) = &self.ranks {
            // This rank's piece of the ring, and on rank 0 the index over every piece.
            let part = &rp.part;
            let poly = particles_polydata_of(rp.setup(), &part.local, &part.own());
            let at = (part.rank(), part.ranks());
            if let Some(name) = crate::ranks::write_piece(&poly, dir, k, at)? {
                parts.push(("particles", name));
            }
        } else if let Some(r) = &self.ring {
            let name = format!("particles_{k:05}.vtp");
            particles_polydata(&r.setup, &r.state).write(&dir.join(&name))?;
            parts.push(("particles", name));
        }
        Ok(parts)
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
