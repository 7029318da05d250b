//! ParaView output of an MPM run: the material points as VTP and the grid as VTU, frame
//! by frame, indexed by `frames/series.pvd`.

use super::Mpm;
use crate::frames::Framed;
use grains_core::vtk::{cell_type, ArrayData, DataArray, PolyData, UnstructuredGrid};
use grains_mpm::grid::GHOST;
use grains_mpm::{Material, Setup, Solver, State};
use std::io;
use std::path::Path;

impl Framed for Mpm {
    fn write_frame(&self, dir: &Path, k: usize) -> io::Result<Vec<(&'static str, String)>> {
        let name = format!("points_{k:05}.vtp");
        points_polydata(&self.setup, &self.state).write(&dir.join(&name))?;
        let mut parts = vec![("points", name)];
        if self.grid_frames {
            let g = format!("grid_{k:05}.vtu");
            grid_vtu(&self.setup, &self.solver).write(&dir.join(&g))?;
            parts.push(("grid", g));
        }
        Ok(parts)
    }
}

/// The material points with their fields, in creation order. Fields of the state
/// only some runs have are written when some body has them: `plastic_strain` (J2),
/// `dissipated_density` (J2, Maxwell), `bond` (bonded interfaces), `temperature` and
/// `thermal_work` (prescribed temperatures).
pub fn points_polydata(setup: &Setup, s: &State) -> PolyData {
    let p = &s.particles;
    let mut order: Vec<usize> = (0..p.len()).collect();
    order.sort_unstable_by_key(|&i| p.id[i]);
    let pos: Vec<_> = order.iter().map(|&i| p.pos[i]).collect();
    let vel: Vec<_> = order.iter().map(|&i| p.vel[i]).collect();
    let f = |g: &dyn Fn(usize) -> f64| order.iter().map(|&i| g(i)).collect::<Vec<f64>>();
    let mut tensor = Vec::with_capacity(6 * p.len());
    for &i in &order {
        let t = p.stress[i];
        // ParaView's symmetric tensor order: XX, YY, ZZ, XY, YZ, XZ.
        tensor.extend_from_slice(&[t.xx, t.yy, t.zz, t.xy, 0.0, 0.0]);
    }
    let mut poly = PolyData::from_points_2d(&pos);
    poly.point_data = vec![
        DataArray::scalar_i64("id", order.iter().map(|&i| p.id[i] as i64).collect()),
        DataArray::scalar_i32("body", order.iter().map(|&i| p.body[i] as i32).collect()),
        DataArray::vector2_f64("velocity", &vel),
        DataArray::new("stress", 6, ArrayData::F64(tensor)),
        DataArray::scalar_f64("pressure", f(&|i| p.stress[i].pressure())),
        DataArray::scalar_f64(
            "principal_stress_difference",
            f(&|i| p.stress[i].principal_difference()),
        ),
        DataArray::scalar_f64("mass", f(&|i| p.mass[i])),
        DataArray::scalar_f64("volume", f(&|i| p.volume(i))),
        DataArray::scalar_f64("jacobian", f(&|i| p.def[i].determinant())),
    ];
    let has =
        |m: fn(&Material) -> bool| setup.bodies.iter().any(|b| m(&setup.materials[b.material]));
    if has(|m| matches!(m, Material::J2Plastic { .. })) {
        poly.point_data.push(DataArray::scalar_f64(
            "plastic_strain",
            f(&|i| p.plastic[i]),
        ));
    }
    if has(|m| matches!(m, Material::J2Plastic { .. } | Material::Maxwell { .. })) {
        poly.point_data.push(DataArray::scalar_f64(
            "dissipated_density",
            f(&|i| p.dissipated[i] / p.volume(i)),
        ));
    }
    if setup.bonds() {
        poly.point_data
            .push(DataArray::scalar_f64("bond", f(&|i| p.bond[i])));
    }
    if setup.bodies.iter().any(|b| b.temperature.is_some()) {
        let temperature: Vec<f64> = setup
            .bodies
            .iter()
            .map(|b| b.temperature.as_ref().map_or(f64::NAN, |h| h.at(s.time)))
            .collect();
        poly.point_data.push(DataArray::scalar_f64(
            "temperature",
            f(&|i| temperature[p.body[i] as usize]),
        ));
        poly.point_data.push(DataArray::scalar_f64(
            "thermal_work",
            f(&|i| p.thermal_work[i]),
        ));
    }
    poly
}

/// The domain's nodes (ghosts left out) with the fields of the last step summed over
/// bodies: mass, centre-of-mass velocity, number of bodies, contact flags (along a
/// periodic y the top row repeats the bottom one).
pub fn grid_vtu(setup: &Setup, w: &Solver) -> UnstructuredGrid {
    let grid = &setup.grid;
    let [nx, ny] = [grid.cells[0] + 1, grid.cells[1] + 1];
    let mut mass = vec![0.0; nx * ny];
    let mut mom = vec![glam::DVec2::ZERO; nx * ny];
    let mut bodies = vec![0i32; nx * ny];
    let mut touched = vec![0i32; nx * ny];
    let wrap = grid.canonical_rows();
    for patch in &w.patches {
        for (k, n) in patch.nodes.iter().enumerate() {
            let [c, r] = patch.stored(k);
            let r = wrap.map_or(r, |w| w.canonical(r));
            if n.m <= 0.0 || c < GHOST || r < GHOST || c - GHOST >= nx || r - GHOST >= ny {
                continue;
            }
            let at = (r - GHOST) * nx + (c - GHOST);
            mass[at] += n.m;
            mom[at] += n.p;
            bodies[at] += 1;
            touched[at] |= n.touched as i32;
        }
    }
    if wrap.is_some() {
        // The top node row is the bottom one.
        for i in 0..nx {
            let (a, z) = (i, (ny - 1) * nx + i);
            mass[z] = mass[a];
            mom[z] = mom[a];
            bodies[z] = bodies[a];
            touched[z] = touched[a];
        }
    }
    let mut u = UnstructuredGrid::default();
    for j in 0..ny {
        for i in 0..nx {
            let x = grid.node_pos([i + GHOST, j + GHOST]);
            u.points.push([x.x, x.y, 0.0]);
        }
    }
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let a = (j * nx + i) as i64;
            u.push_cell(
                cell_type::QUAD,
                &[a, a + 1, a + 1 + nx as i64, a + nx as i64],
            );
        }
    }
    let vel: Vec<_> = mass
        .iter()
        .zip(&mom)
        .map(|(m, p)| if *m > 0.0 { *p / *m } else { glam::DVec2::ZERO })
        .collect();
    u.point_data = vec![
        DataArray::scalar_f64("mass", mass),
        DataArray::vector2_f64("velocity", &vel),
        DataArray::scalar_i32("bodies", bodies),
        DataArray::scalar_i32("contact", touched),
    ];
    u
}
