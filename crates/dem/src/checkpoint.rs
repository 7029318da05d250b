//! Exact binary snapshots of a [`State`], so a run can stop and continue bitwise as if it
//! had never stopped: every particle field, the neighbour list in its current order with
//! its tangential history, wall springs and expanding frame, the last wall loads and
//! where each wall has got to (its pose: a moving wall is placed, not replayed).
//!
//! Layout: a sequence of tagged little-endian arrays ([`grains_core::snapshot`]), in a
//! fixed order. Readers check every length against the particle and
//! entry counts and refuse anything inconsistent; integrity of the bytes themselves is
//! the container's job (the CLI adds a checksum over the whole file).

use crate::integrate::WallLoad;
use crate::math::{self, AngVector, Components, Tangent, Vector};
use crate::neighbours::ContactList;
use crate::particles::Particles;
use crate::setup::Setup;
use crate::step::State;
use crate::verlet::Comoving;
use crate::walls::Pose;
pub use grains_core::snapshot::SnapshotError;
use grains_core::snapshot::{get_f64, get_u32, get_u64, put_f64, put_u32, put_u64};
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
    math::put(w, &p.pos)?;
    math::put(w, &p.vel)?;
    math::put(w, &p.omega)?;
    put_f64(w, &p.radius)?;
    put_f64(w, &p.inv_mass)?;
    put_f64(w, &p.inv_inertia)?;
    put_u32(w, &p.material.iter().map(|&m| m as u32).collect::<Vec<_>>())?;
    math::put(w, &p.force)?;
    math::put(w, &p.torque)?;
    put_u32(w, &c.row)?;
    put_u32(w, &c.nbr)?;
    // A granular list keeps no linear springs; the file holds zeros in their place, so
    // its layout does not depend on the law.
    match c.shear.len() == c.nbr.len() {
        true => math::put(w, &c.shear)?,
        false => math::put(w, &vec![Tangent::default(); c.nbr.len()])?,
    }
    // A granular list keeps its reactions in its pools, for the touching pairs alone:
    // the file holds them per entry (zero where apart), as the linear law's list does.
    match c.fpair.len() == c.nbr.len() && c.ftan.len() == c.nbr.len() {
        true => {
            math::put(w, &c.fpair)?;
            math::put(w, &c.ftan)?;
        }
        false => {
            let (fpair, ftan): (Vec<Vector>, Vec<AngVector>) =
                (0..c.nbr.len()).map(|e| c.reaction(e)).unzip();
            math::put(w, &fpair)?;
            math::put(w, &ftan)?;
        }
    }
    put_u32(w, &c.rev_row)?;
    put_u32(w, &c.rev_entry)?;
    put_u64(w, &c.wall_near)?;
    match c.wall_shear.is_empty() {
        // The granular law keeps none: the file holds zeros there, as before.
        true => math::put(w, &vec![Tangent::default(); c.wall_near.len() * c.n_walls])?,
        false => math::put(w, &c.wall_shear)?,
    }
    math::put(w, &c.pos_at_build)?;
    let frame: Vec<f64> = c
        .frame
        .map(|f| {
            let mut v = Vector::flatten(&[f.centre, f.shift]);
            v.push(f.radial);
            v
        })
        .unwrap_or_default();
    put_f64(w, &frame)?;
    let loads: Vec<f64> = state
        .wall_loads
        .iter()
        .flat_map(|l| {
            let mut v = Vector::flatten(&[l.force]);
            v.extend(AngVector::flatten(&[l.torque]));
            v.push(l.contacts as f64);
            v
        })
        .collect();
    put_f64(w, &loads)?;
    // The granular law's histories (empty under the linear law).
    let history: Vec<f64> = (0..c.len())
        .filter_map(|e| c.granular(e))
        .flat_map(|h| h.into_iter())
        .collect();
    put_f64(w, &history)?;
    put_f64(w, &c.wall_history.full())?;
    let poses: Vec<f64> = state
        .walls
        .iter()
        .flat_map(|p| {
            let mut v = Vector::flatten(&[p.at]);
            v.extend(AngVector::flatten(&[p.angle]));
            v
        })
        .collect();
    put_f64(w, &poses)
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
    if state.walls.len() != setup.walls.len() {
        return Err(SnapshotError::Invalid(format!(
            "{} wall poses, the set-up has {} walls",
            state.walls.len(),
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
        pos: math::get(r, n)?,
        vel: math::get(r, n)?,
        omega: math::get(r, n)?,
        radius: get_f64(r, n)?,
        inv_mass: get_f64(r, n)?,
        inv_inertia: get_f64(r, n)?,
        material: Vec::new(),
        force: Vec::new(),
        torque: Vec::new(),
        // The running ledgers ride in the caller's tail ([`crate::ledger_sums`]).
        ledger: Vec::new(),
    };
    p.material = get_u32(r, n)?
        .into_iter()
        .map(|m| u16::try_from(m).unwrap_or(u16::MAX))
        .collect();
    p.force = math::get(r, n)?;
    p.torque = math::get(r, n)?;
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
    c.shear = math::get::<Tangent>(r, m)?;
    c.fpair = math::get(r, m)?;
    c.ftan = math::get(r, m)?;
    c.rev_row = get_u32(r, n + 1)?;
    c.rev_entry = get_u32(r, m)?;
    c.wall_near = get_u64(r, n)?;
    c.wall_shear = math::get(r, n * n_walls)?;
    c.pos_at_build = math::get(r, n)?;
    let d = Vector::N;
    let frame = get_f64(r, 2 * d + 1)?;
    c.frame = match frame.len() {
        0 => None,
        k if k == 2 * d + 1 => Some(Comoving {
            centre: Vector::from_slice(&frame[..d]),
            shift: Vector::from_slice(&frame[d..2 * d]),
            radial: frame[2 * d],
        }),
        k => {
            return Err(SnapshotError::Invalid(format!(
                "expanding frame: {k} values, expected 0 or {}",
                2 * d + 1
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
    // Per wall: the force, the torque and the contact count.
    let stride = Vector::N + AngVector::N + 1;
    let loads = get_f64(r, stride * crate::setup::MAX_WALLS)?;
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
    // The owners and the reverse index are derived from the rows and the ids: made
    // here, not trusted from the file, so that a checkpoint written before the pass
    // summed in id order (its reverse index held cross-chunk entries only, in storage
    // order) resumes in id order too.
    c.index_reverse(&p.id);
    if n_walls < 64 && c.wall_near.iter().any(|&m| m >> n_walls != 0) {
        return Err(SnapshotError::Invalid(format!(
            "a particle is near a wall beyond the {n_walls} walls"
        )));
    }
    if loads.len() % stride != 0 {
        return Err(SnapshotError::Invalid("wall loads".into()));
    }
    let width = crate::granular::WIDTH;
    let history = get_f64(r, width * m)?;
    let wall_history = get_f64(r, width * n * n_walls)?;
    for (what, got, want) in [
        ("granular histories", history.len(), width * m),
        (
            "granular wall histories",
            wall_history.len(),
            width * n * n_walls,
        ),
    ] {
        if got != 0 && got != want {
            return Err(SnapshotError::Invalid(format!(
                "{what}: {got} values, expected 0 or {want}"
            )));
        }
    }
    let rows = |f: Vec<f64>| -> Vec<[f64; crate::granular::WIDTH]> {
        f.chunks_exact(width)
            .map(|h| h.try_into().expect("a whole history"))
            .collect()
    };
    let history = rows(history);
    c.history = match history.is_empty() {
        true => Default::default(),
        false => crate::history::Histories::from_entries(&c.owner, n.div_ceil(crate::CHUNK), |e| {
            Some(history[e])
        }),
    };
    c.wall_history = crate::history::Narrow::from_records(&rows(wall_history));
    let pose = Vector::N + AngVector::N;
    let walls = get_f64(r, pose * n_walls)?;
    same("wall poses", walls.len(), pose * n_walls)?;
    let walls = walls
        .chunks_exact(pose)
        .map(|p| Pose {
            at: Vector::from_slice(p),
            angle: AngVector::from_slice(&p[Vector::N..]),
        })
        .collect();
    let wall_loads = loads
        .chunks_exact(stride)
        .map(|l| WallLoad {
            force: Vector::from_slice(l),
            torque: AngVector::from_slice(&l[Vector::N..]),
            contacts: l[stride - 1] as u32,
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
        walls,
    })
}
