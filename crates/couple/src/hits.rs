//! The grains touching the charge's edge, in one canonical order on every rank.
//!
//! Every rank steps the whole charge, so every rank must add the same nodal forces in
//! the same order: the penalty pass sums over the contacts of every grain on the edge
//! (the length of edge each node's grains cover, the reactions, the springs' energy and
//! frequency bound). Each rank finds the contacts of the grains it owns; the contacts
//! of every rank are gathered (a few thousand at most: the grains of the edge's layer)
//! and put in the order of (grain id, edge), which no storage order and no rank count
//! changes. A serial run takes the same order, so its sums are the distributed ones.

use crate::penalty::Touch;
use glam::DVec2;
use grains_dem::Reduce;

/// A grain touching a boundary edge, with what the sums over every contact read of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// The grain's global id.
    pub id: u32,
    /// The boundary edge's index.
    pub edge: u32,
    /// The contact.
    pub touch: Touch,
    /// Whether the contact is with the edge's first node (a convex corner), not its span.
    pub corner: bool,
    /// The grain's radius (m).
    pub radius: f64,
    /// The grain's mass (kg/m).
    pub mass: f64,
    /// The grain's centre (m).
    pub pos: DVec2,
    /// The grain's index in this rank's particles when it is this rank's own.
    pub local: Option<u32>,
}

/// Words of one hit on the wire.
const WORDS: usize = 11;

/// Every rank's hits (`own`: this rank's, with their `local` index) in ascending (id,
/// edge): the same list on every rank, each hit's `local` set on its owner's rank only.
pub fn canonical(mut own: Vec<Hit>, comm: &dyn Reduce) -> Vec<Hit> {
    if comm.ranks() > 1 {
        let me = comm.rank() as u64;
        let mut words = Vec::with_capacity(own.len() * WORDS);
        for h in &own {
            put(&mut words, h, me);
        }
        own = comm
            .gather(words)
            .chunks_exact(WORDS)
            .map(|w| get(w, me))
            .collect();
    }
    own.sort_unstable_by_key(|h| (h.id, h.edge));
    own
}

fn put(w: &mut Vec<u64>, h: &Hit, rank: u64) {
    w.push(u64::from(h.id) << 32 | u64::from(h.edge));
    w.push(rank << 1 | u64::from(h.corner));
    w.push(h.local.map_or(u64::MAX, u64::from));
    let t = &h.touch;
    w.extend(
        [
            t.normal.x, t.normal.y, t.overlap, t.at, h.radius, h.mass, h.pos.x, h.pos.y,
        ]
        .map(f64::to_bits),
    );
}

fn get(w: &[u64], me: u64) -> Hit {
    let f = |k: usize| f64::from_bits(w[k]);
    Hit {
        id: (w[0] >> 32) as u32,
        edge: w[0] as u32,
        corner: w[1] & 1 == 1,
        local: (w[1] >> 1 == me).then_some(w[2] as u32),
        touch: Touch {
            normal: DVec2::new(f(3), f(4)),
            overlap: f(5),
            at: f(6),
        },
        radius: f(7),
        mass: f(8),
        pos: DVec2::new(f(9), f(10)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_hit_survives_the_wire() {
        let h = Hit {
            id: 7,
            edge: 123_456,
            touch: Touch {
                normal: DVec2::new(0.6, -0.8),
                overlap: 1e-6,
                at: 0.25,
            },
            corner: true,
            radius: 2e-4,
            mass: 3.2e-4,
            pos: DVec2::new(-1e-2, 3e-3),
            local: Some(42),
        };
        let mut w = Vec::new();
        put(&mut w, &h, 3);
        assert_eq!(w.len(), WORDS);
        assert_eq!(get(&w, 3), h);
        assert_eq!(get(&w, 2), Hit { local: None, ..h });
    }
}
