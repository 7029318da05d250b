//! Exact binary snapshots of the particle side of a coupled run: the DEM state (its
//! own snapshot), the charge–particle contact that carries over from one step to the
//! next (the candidate list and where the edge stood when it was made, each node's
//! initial edge length, the springs' frequency bound that sets the next step), the
//! box of the DEM cell grid and the energy ledger.
//!
//! What each force evaluation recomputes before anyone reads it (the contact count,
//! the deepest contact, the springs' energy) is kept too, so that a sample taken
//! right after a resume reads what it would have read.

use crate::step::Ring;
use grains_core::snapshot::{
    get_f64, get_f64_exact, get_u32, get_u64_exact, get_vec2_exact, put_f64, put_u32, put_u64,
    put_vec2, SnapshotError,
};
use grains_dem::ledger::LEDGER_WORDS;
use grains_dem::LedgerSums;
use std::io::{self, Read, Write};

/// Writes the ring.
pub fn write(ring: &Ring, w: &mut impl Write) -> io::Result<()> {
    grains_dem::checkpoint::write(&ring.state, w)?;
    let c = &ring.coupling;
    put_u64(
        w,
        &[
            c.builds,
            c.contacts as u64,
            c.nodes_at_build.len() as u64,
            c.apex.len() as u64,
            c.node_length.len() as u64,
        ],
    )?;
    put_f64(
        w,
        &[
            c.stiffness,
            c.skin,
            c.max_penetration_ratio,
            c.energy,
            c.radial_force,
            c.omega2_max,
            c.offset,
        ],
    )?;
    let pairs: Vec<u32> = c.candidates.iter().flat_map(|&(i, e)| [i, e]).collect();
    put_u32(w, &pairs)?;
    put_vec2(w, &c.nodes_at_build)?;
    put_u32(w, &c.apex)?;
    put_f64(w, &c.node_length)?;
    put_vec2(w, &[ring.grid_box.0, ring.grid_box.1])?;
    // The ledger: the exact sums of what left the run (their words' bits as numbers),
    // then every grain's running ledger in ascending id, so that a resumed ring's
    // ledger goes on as the straight run's, bit for bit.
    let ledger: Vec<f64> = ring
        .state
        .ledger
        .as_ref()
        .map(|l| l.to_words().into_iter().map(f64::from_bits).collect())
        .unwrap_or_default();
    put_f64(w, &ledger)?;
    put_f64(w, &grains_dem::ledger_sums::rows_by_id(&ring.state))
}

/// Reads a snapshot written by [`write`] into `ring`, a ring made from the same
/// scenario (its set-up is kept; the state and the contact are replaced). `max_particles`
/// bounds allocations; `nodes` and `edges` are the charge's node and boundary-edge counts.
/// Refuses a snapshot of a different ring or coupling.
pub fn read_into(
    ring: &mut Ring,
    r: &mut impl Read,
    max_particles: usize,
    nodes: usize,
    edges: usize,
) -> Result<(), SnapshotError> {
    let n = ring.state.particles.len();
    let state = grains_dem::checkpoint::read(r, max_particles.min(n))?;
    grains_dem::checkpoint::fits(&state, &ring.setup)?;
    if state.particles.len() != n || state.contacts.n_walls != ring.state.contacts.n_walls {
        return Err(SnapshotError::Invalid(format!(
            "the checkpoint's ring has {} particles and {} walls, the scenario's {n} and {}",
            state.particles.len(),
            state.contacts.n_walls,
            ring.state.contacts.n_walls
        )));
    }
    let head = get_u64_exact(r, 5, "coupling header")?;
    let scalars = get_f64_exact(r, 7, "coupling scalars")?;
    let c = &ring.coupling;
    if scalars[0].to_bits() != c.stiffness.to_bits() || scalars[1].to_bits() != c.skin.to_bits() {
        return Err(SnapshotError::Invalid(format!(
            "the checkpoint's coupling has stiffness {:e} N/m and skin {:e} m, the scenario's {:e} and {:e}",
            scalars[0], scalars[1], c.stiffness, c.skin
        )));
    }
    // A ring starts with a detection and a force evaluation, which size all three.
    let (built, apexes, lengths) = (head[2] as usize, head[3] as usize, head[4] as usize);
    if built != edges || apexes != edges || lengths != nodes {
        return Err(SnapshotError::Invalid(format!(
            "the checkpoint's coupling covers {built} edges and {lengths} nodes, the charge has {edges} and {nodes}"
        )));
    }
    // At most every particle with every edge (the reader allocates only what is there).
    let pairs = get_u32(r, n.saturating_mul(edges).saturating_mul(2))?;
    if pairs.len() % 2 != 0
        || pairs
            .chunks_exact(2)
            .any(|p| p[0] as usize >= n || p[1] as usize >= edges)
    {
        return Err(SnapshotError::Invalid(
            "a charge–particle candidate is out of range".into(),
        ));
    }
    let nodes_at_build = get_vec2_exact(r, built, "edge positions at the last detection")?;
    let apex = get_u32(r, apexes)?;
    if apex.len() != apexes || apex.iter().any(|&a| a as usize >= nodes) {
        return Err(SnapshotError::Invalid(
            "an edge's apex is out of range".into(),
        ));
    }
    let node_length = get_f64_exact(r, lengths, "initial edge lengths")?;
    let grid_box = get_vec2_exact(r, 2, "grid box")?;
    let ledger = get_f64(r, LedgerSums::WORDS)?;
    let departed = match ledger.len() {
        0 => None,
        n => Some(
            LedgerSums::from_words(&ledger.iter().map(|x| x.to_bits()).collect::<Vec<_>>())
                .ok_or_else(|| {
                    SnapshotError::Invalid(format!(
                        "energy ledger: {n} values, expected 0 or {}{}",
                        LedgerSums::WORDS,
                        if n == 5 {
                            " (written by an older build, before each grain kept its own \
                             ledger: it cannot go on; start the run again)"
                        } else {
                            ""
                        }
                    ))
                })?,
        ),
    };
    let mut state = state;
    if departed.is_some() {
        let rows = get_f64(r, LEDGER_WORDS * state.particles.len())?;
        grains_dem::ledger_sums::read_rows(&mut state, &rows).map_err(SnapshotError::Invalid)?;
    }

    let c = &mut ring.coupling;
    c.builds = head[0];
    c.contacts = head[1] as usize;
    c.max_penetration_ratio = scalars[2];
    c.energy = scalars[3];
    c.radial_force = scalars[4];
    c.omega2_max = scalars[5];
    c.offset = scalars[6];
    c.candidates = pairs.chunks_exact(2).map(|p| (p[0], p[1])).collect();
    c.nodes_at_build = nodes_at_build;
    c.apex = apex;
    c.node_length = node_length;
    // Recomputed by the next force evaluation, before anything reads it.
    c.deepest = None;
    ring.grid_box = (grid_box[0], grid_box[1]);
    ring.state = state;
    ring.state.ledger = departed;
    Ok(())
}
