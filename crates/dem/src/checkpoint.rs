//! Exact binary snapshots of a [`State`], so a run can stop and continue bitwise as if it
//! had never stopped: every particle field, the neighbour list in its current order with
//! its tangential history, wall springs and expanding frame, and the last wall loads.
//!
//! Layout: a sequence of tagged little-endian arrays ([`grains_core::snapshot`]), in a
//! fixed order. Readers check every length against the particle and
//! entry counts and refuse anything inconsistent; integrity of the bytes themselves is
//! the container's job (the CLI adds a checksum over the whole file).

use crate::integrate::WallLoad;
use crate::neighbours::ContactList;
use crate::particles::Particles;
use crate::setup::Setup;
use crate::step::State;
use crate::verlet::Comoving;
use glam::DVec2;
pub use grains_core::snapshot::SnapshotError;
use grains_core::snapshot::{
    get_f64, get_u32, get_u64, get_vec2, put_f64, put_u32, put_u64, put_vec2,
};
use std::io::{self, Read, Write};

/// Writes the state.
pub fn write(state: &State, w: &mut impl Write) -> io::Result<()> {
    let p = &state.particles;
    let c = &state.contacts;
    put_u64(
        w,
        &[state.step, state.time.to_bits(), c.builds, c.n_walls as u64],
    )?;
    put_u32(w, &p.id)?;
    put_vec2(w, &p.pos)?;
    put_vec2(w, &p.vel)?;
    put_f64(w, &p.omega)?;
    put_f64(w, &p.radius)?;
    put_f64(w, &p.inv_mass)?;
    put_f64(w, &p.inv_inertia)?;
    put_u32(w, &p.material.iter().map(|&m| m as u32).collect::<Vec<_>>())?;
    put_vec2(w, &p.force)?;
    put_f64(w, &p.torque)?;
    put_u32(w, &c.row)?;
    put_u32(w, &c.nbr)?;
    put_f64(w, &c.shear)?;
    put_vec2(w, &c.fpair)?;
    put_f64(w, &c.ftan)?;
    put_u32(w, &c.rev_row)?;
    put_u32(w, &c.rev_entry)?;
    put_u64(w, &c.wall_near)?;
    put_f64(w, &c.wall_shear)?;
    put_vec2(w, &c.pos_at_build)?;
    let frame: Vec<f64> = c
        .frame
        .map(|f| vec![f.centre.x, f.centre.y, f.shift.x, f.shift.y, f.radial])
        .unwrap_or_default();
    put_f64(w, &frame)?;
    let loads: Vec<f64> = state
        .wall_loads
        .iter()
        .flat_map(|l| [l.force.x, l.force.y, l.torque, l.contacts as f64])
        .collect();
    put_f64(w, &loads)
}

/// Whether a state read back fits the set-up it is to run with: its materials and walls.
pub fn fits(state: &State, setup: &Setup) -> Result<(), SnapshotError> {
    let materials = setup.materials.len();
    if let Some(&m) = state
        .particles
        .material
        .iter()
        .find(|&&m| m as usize >= materials)
    {
        return Err(SnapshotError::Invalid(format!(
            "a particle of material {m}, the set-up has {materials} materials"
        )));
    }
    if state.contacts.n_walls != setup.walls.len() {
        return Err(SnapshotError::Invalid(format!(
            "{} walls, the set-up has {}",
            state.contacts.n_walls,
            setup.walls.len()
        )));
    }
    Ok(())
}

/// Reads a state written by [`write`], checking that every array fits the others.
/// `max_particles` bounds allocations so a corrupted length cannot exhaust memory.
pub fn read(r: &mut impl Read, max_particles: usize) -> Result<State, SnapshotError> {
    let head = get_u64(r, 4)?;
    if head.len() != 4 {
        return Err(SnapshotError::Invalid("bad header".into()));
    }
    let lim = max_particles;
    let elim = 64 * max_particles + 64;
    let id = get_u32(r, lim)?;
    let n = id.len();
    let mut p = Particles {
        id,
        pos: get_vec2(r, n)?,
        vel: get_vec2(r, n)?,
        omega: get_f64(r, n)?,
        radius: get_f64(r, n)?,
        inv_mass: get_f64(r, n)?,
        inv_inertia: get_f64(r, n)?,
        material: Vec::new(),
        force: Vec::new(),
        torque: Vec::new(),
    };
    p.material = get_u32(r, n)?
        .into_iter()
        .map(|m| u16::try_from(m).unwrap_or(u16::MAX))
        .collect();
    p.force = get_vec2(r, n)?;
    p.torque = get_f64(r, n)?;
    let n_walls = head[3] as usize;
    if n_walls > crate::setup::MAX_WALLS {
        return Err(SnapshotError::Invalid(format!(
            "{n_walls} walls (at most {})",
            crate::setup::MAX_WALLS
        )));
    }
    let mut c = ContactList {
        row: get_u32(r, n + 1)?,
        nbr: get_u32(r, elim)?,
        ..Default::default()
    };
    let m = c.nbr.len();
    c.shear = get_f64(r, m)?;
    c.fpair = get_vec2(r, m)?;
    c.ftan = get_f64(r, m)?;
    c.rev_row = get_u32(r, n + 1)?;
    c.rev_entry = get_u32(r, m)?;
    c.wall_near = get_u64(r, n)?;
    c.wall_shear = get_f64(r, n * n_walls)?;
    c.pos_at_build = get_vec2(r, n)?;
    let frame = get_f64(r, 5)?;
    c.frame = match frame.len() {
        0 => None,
        5 => Some(Comoving {
            centre: DVec2::new(frame[0], frame[1]),
            shift: DVec2::new(frame[2], frame[3]),
            radial: frame[4],
        }),
        k => {
            return Err(SnapshotError::Invalid(format!(
                "expanding frame: {k} values, expected 0 or 5"
            )))
        }
    };
    // Made from the build positions as the rebuild made them.
    c.normal_at_build = match &c.frame {
        Some(f) => c.pos_at_build.iter().map(|&x| f.normal(x)).collect(),
        None => Vec::new(),
    };
    c.n_walls = n_walls;
    c.builds = head[2];
    let loads = get_f64(r, 4 * 64)?;
    let same = |what: &str, got: usize, want: usize| {
        if got == want {
            Ok(())
        } else {
            Err(SnapshotError::Invalid(format!(
                "{what}: {got} values, expected {want}"
            )))
        }
    };
    for (what, got) in [
        ("positions", p.pos.len()),
        ("velocities", p.vel.len()),
        ("angular velocities", p.omega.len()),
        ("radii", p.radius.len()),
        ("masses", p.inv_mass.len()),
        ("inertias", p.inv_inertia.len()),
        ("materials", p.material.len()),
        ("forces", p.force.len()),
        ("torques", p.torque.len()),
        ("wall masks", c.wall_near.len()),
        ("build positions", c.pos_at_build.len()),
    ] {
        same(what, got, n)?;
    }
    same("neighbour rows", c.row.len(), n + 1)?;
    same("reverse rows", c.rev_row.len(), n + 1)?;
    same("wall springs", c.wall_shear.len(), n * n_walls)?;
    for (what, got) in [
        ("springs", c.shear.len()),
        ("pair forces", c.fpair.len()),
        ("tangential forces", c.ftan.len()),
    ] {
        same(what, got, m)?;
    }
    if c.row.first() != Some(&0)
        || c.row.last().copied().unwrap_or(0) as usize != m
        || c.row.windows(2).any(|w| w[0] > w[1])
    {
        return Err(SnapshotError::Invalid(
            "neighbour rows do not index the entries".into(),
        ));
    }
    if c.nbr.iter().any(|&j| j as usize >= n) || c.rev_entry.iter().any(|&e| e as usize >= m) {
        return Err(SnapshotError::Invalid(
            "a neighbour index is out of range".into(),
        ));
    }
    if c.rev_row.last().copied().unwrap_or(0) as usize != c.rev_entry.len()
        || c.rev_row.windows(2).any(|w| w[0] > w[1])
    {
        return Err(SnapshotError::Invalid(
            "reverse rows do not index the reverse entries".into(),
        ));
    }
    // Derived, not stored; the rows were checked above.
    c.index_owners();
    // Ids index the springs' history at the next rebuild: each of 0..n once.
    let mut seen = vec![false; n];
    for &i in &p.id {
        match seen.get_mut(i as usize) {
            Some(s) if !*s => *s = true,
            _ => {
                return Err(SnapshotError::Invalid(format!(
                    "particle id {i} out of range or repeated ({n} particles)"
                )))
            }
        }
    }
    if n_walls < 64 && c.wall_near.iter().any(|&m| m >> n_walls != 0) {
        return Err(SnapshotError::Invalid(format!(
            "a particle is near a wall beyond the {n_walls} walls"
        )));
    }
    if loads.len() % 4 != 0 {
        return Err(SnapshotError::Invalid("wall loads".into()));
    }
    let wall_loads = loads
        .chunks_exact(4)
        .map(|l| WallLoad {
            force: DVec2::new(l[0], l[1]),
            torque: l[2],
            contacts: l[3] as u32,
        })
        .collect();
    Ok(State {
        particles: p,
        contacts: c,
        wall_loads,
        time: f64::from_bits(head[1]),
        step: head[0],
        // The energy ledger is an optional measurement, not part of the snapshot: a
        // resumed run that wants one starts it afresh.
        ledger: None,
    })
}
