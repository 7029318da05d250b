//! Checkpoints of FEM–DEM runs: the run's own scalars (initial energy, step bounds and
//! extremes), the charge ([`grains_fem::checkpoint`]) and the ring
//! ([`grains_couple::checkpoint`]), so that a run stopped at a checkpoint goes on bitwise
//! as if it had never stopped. A run of hours (xue-2019 test 1) can then span sessions.

use super::Blast;
use grains_core::snapshot::{get_f64_exact, get_u64_exact, put_f64, put_u64, SnapshotError};

/// Largest ring a checkpoint may hold (bounds allocations while reading).
const MAX_PARTICLES: usize = 1 << 31;

impl Blast {
    /// The run's state as checkpoint bytes.
    pub fn snapshot(&self) -> Vec<u8> {
        let mut w = Vec::new();
        let fields = [
            self.e0,
            self.dt,
            self.dt_range.0,
            self.dt_range.1,
            self.max_penetration,
            self.dt_particles,
            self.dt_floor,
        ];
        // Writing into memory cannot fail.
        put_f64(&mut w, &fields).expect("in memory");
        put_u64(&mut w, &[self.ring.is_some() as u64]).expect("in memory");
        grains_fem::checkpoint::write(&self.charge, &mut w).expect("in memory");
        if let Some(r) = &self.ring {
            grains_couple::checkpoint::write(r, &mut w).expect("in memory");
        }
        w
    }

    /// Replaces the state of this run, started afresh from the same scenario, by the
    /// one in `bytes` (from [`Blast::snapshot`]).
    pub fn restore(&mut self, bytes: &[u8]) -> Result<(), SnapshotError> {
        let r = &mut &bytes[..];
        let f = get_f64_exact(r, 7, "run scalars")?;
        let has_ring = match get_u64_exact(r, 1, "ring flag")?[0] {
            0 => false,
            1 => true,
            k => return Err(SnapshotError::Invalid(format!("ring flag {k}"))),
        };
        if has_ring != self.ring.is_some() {
            return Err(SnapshotError::Invalid(format!(
                "the checkpoint {} a ring, the scenario {}",
                if has_ring { "has" } else { "has no" },
                if self.ring.is_some() {
                    "has one"
                } else {
                    "none"
                }
            )));
        }
        grains_fem::checkpoint::read_into(&mut self.charge, r)?;
        if let Some(ring) = self.ring.as_mut() {
            let (nodes, edges) = (self.charge.n_nodes(), self.charge.boundary.len());
            grains_couple::checkpoint::read_into(ring, r, MAX_PARTICLES, nodes, edges)?;
        }
        if !r.is_empty() {
            return Err(SnapshotError::Invalid(format!(
                "{} bytes left over after the state",
                r.len()
            )));
        }
        self.e0 = f[0];
        self.dt = f[1];
        self.dt_range = (f[2], f[3]);
        self.max_penetration = f[4];
        self.dt_particles = f[5];
        self.dt_floor = f[6];
        Ok(())
    }
}
