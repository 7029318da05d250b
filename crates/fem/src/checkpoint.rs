//! Exact binary snapshots of a [`Charge`], so a run can stop and continue bitwise: every
//! node and element field, the clock and the work done on the charge.
//!
//! The topology (triangles, boundary edges, the node → element index) is not a state:
//! the scenario's mesher makes it again. The snapshot keeps the triangles and boundary
//! edges only to check that the charge it is read into has the same mesh.

use crate::state::Charge;
use glam::DVec2;
use grains_core::snapshot::{
    get_f64_exact, get_u32, get_u64_exact, get_vec2_exact, put_f64, put_u32, put_u64, put_vec2,
    SnapshotError,
};
use std::io::{self, Read, Write};

/// Writes the charge.
pub fn write(c: &Charge, w: &mut impl Write) -> io::Result<()> {
    put_u64(w, &[c.step, c.n_nodes() as u64, c.n_elems() as u64])?;
    put_f64(w, &[c.time, c.dt_stable, c.work_external, c.work_damping])?;
    let tri: Vec<u32> = c.elems.tri.iter().flatten().copied().collect();
    put_u32(w, &tri)?;
    let boundary: Vec<u32> = c.boundary.iter().flatten().copied().collect();
    put_u32(w, &boundary)?;
    let n = &c.nodes;
    for v in [&n.pos, &n.pos_prev, &n.vel, &n.f_int, &n.f_ext, &n.f_damp] {
        put_vec2(w, v)?;
    }
    put_f64(w, &n.mass)?;
    let e = &c.elems;
    for v in [
        &e.mass,
        &e.area_ref,
        &e.area,
        &e.energy,
        &e.pressure,
        &e.q,
        &e.lambda,
        &e.t_light,
        &e.d_eff,
        &e.r_light,
        &e.sound,
        &e.arrival,
        &e.dt_stable,
    ] {
        put_f64(w, v)?;
    }
    let dev: Vec<f64> = e.dev.iter().flatten().copied().collect();
    put_f64(w, &dev)?;
    let f_node: Vec<DVec2> = e.f_node.iter().flatten().copied().collect();
    put_vec2(w, &f_node)
}

/// Reads a snapshot written by [`write`] into `c`, a charge made from the same mesh
/// (its topology is kept; every state field is replaced). Refuses a snapshot of a
/// different mesh.
pub fn read_into(c: &mut Charge, r: &mut impl Read) -> Result<(), SnapshotError> {
    let (nn, ne) = (c.n_nodes(), c.n_elems());
    let head = get_u64_exact(r, 3, "charge header")?;
    if head[1] != nn as u64 || head[2] != ne as u64 {
        return Err(SnapshotError::Invalid(format!(
            "the checkpoint's charge has {} nodes and {} elements, the scenario's mesh {nn} and {ne}",
            head[1], head[2]
        )));
    }
    let clock = get_f64_exact(r, 4, "charge clock")?;
    let tri: Vec<u32> = c.elems.tri.iter().flatten().copied().collect();
    let boundary: Vec<u32> = c.boundary.iter().flatten().copied().collect();
    if get_u32(r, 3 * ne)? != tri || get_u32(r, 2 * c.boundary.len())? != boundary {
        return Err(SnapshotError::Invalid(
            "the checkpoint's charge mesh differs from the scenario's".into(),
        ));
    }
    let mut vec2s = Vec::with_capacity(6);
    for what in [
        "node positions",
        "previous node positions",
        "node velocities",
        "internal forces",
        "external forces",
        "damping forces",
    ] {
        vec2s.push(get_vec2_exact(r, nn, what)?);
    }
    let node_mass = get_f64_exact(r, nn, "node masses")?;
    let mut f64s = Vec::with_capacity(13);
    for what in [
        "element masses",
        "reference areas",
        "areas",
        "energies",
        "pressures",
        "viscosities",
        "burn fractions",
        "lighting times",
        "burn lengths",
        "lighting distances",
        "sound speeds",
        "arrival times",
        "element steps",
    ] {
        f64s.push(get_f64_exact(r, ne, what)?);
    }
    let dev = get_f64_exact(r, 3 * ne, "deviatoric stresses")?;
    let f_node = get_vec2_exact(r, 3 * ne, "element nodal forces")?;

    let n = &mut c.nodes;
    let mut v = vec2s.into_iter();
    for field in [
        &mut n.pos,
        &mut n.pos_prev,
        &mut n.vel,
        &mut n.f_int,
        &mut n.f_ext,
        &mut n.f_damp,
    ] {
        *field = v.next().expect("six node fields");
    }
    n.mass = node_mass;
    let e = &mut c.elems;
    let mut v = f64s.into_iter();
    for field in [
        &mut e.mass,
        &mut e.area_ref,
        &mut e.area,
        &mut e.energy,
        &mut e.pressure,
        &mut e.q,
        &mut e.lambda,
        &mut e.t_light,
        &mut e.d_eff,
        &mut e.r_light,
        &mut e.sound,
        &mut e.arrival,
        &mut e.dt_stable,
    ] {
        *field = v.next().expect("thirteen element fields");
    }
    e.dev = dev.chunks_exact(3).map(|s| [s[0], s[1], s[2]]).collect();
    e.f_node = f_node.chunks_exact(3).map(|s| [s[0], s[1], s[2]]).collect();
    c.step = head[0];
    [c.time, c.dt_stable, c.work_external, c.work_damping] =
        [clock[0], clock[1], clock[2], clock[3]];
    Ok(())
}
