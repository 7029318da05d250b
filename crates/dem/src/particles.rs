//! Per-field (structure-of-arrays) particle storage.

use crate::math::{AngVector, Vector};

/// All particles, one vector per field. Index order changes when the engine re-sorts
/// particles spatially; `id` is the stable identity given at creation.
#[derive(Clone, Debug, Default)]
pub struct Particles {
    /// Stable identity (0..N at creation).
    pub id: Vec<u32>,
    /// Centre position (m).
    pub pos: Vec<Vector>,
    /// Velocity (m/s).
    pub vel: Vec<Vector>,
    /// Angular velocity (rad/s; in 2D about z, counter-clockwise positive).
    pub omega: Vec<AngVector>,
    /// Radius (m).
    pub radius: Vec<f64>,
    /// 1 / mass (per unit thickness in 2D).
    pub inv_mass: Vec<f64>,
    /// 1 / moment of inertia (per unit thickness in 2D).
    pub inv_inertia: Vec<f64>,
    /// Material index into the scenario's material list.
    pub material: Vec<u16>,
    /// Contact force (particles and walls) of the last force evaluation; gravity acts as
    /// an acceleration and is not included.
    pub force: Vec<Vector>,
    /// Total torque of the last force evaluation.
    pub torque: Vec<AngVector>,
    /// Each particle's running energy ledger while the ledger is kept (empty without:
    /// [`crate::ledger_sums`]).
    pub ledger: Vec<crate::ledger_sums::LedgerRow>,
}

impl Particles {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// True when there are no particles.
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// Appends a particle of the given density and inertia factor (I = f m r²), at rest
    /// unless `vel`/`omega` say otherwise.
    #[allow(clippy::too_many_arguments)]
    pub fn push(
        &mut self,
        pos: Vector,
        radius: f64,
        density: f64,
        inertia_factor: f64,
        material: u16,
        vel: Vector,
        omega: AngVector,
    ) {
        let mass = crate::math::mass(density, radius);
        self.id.push(self.pos.len() as u32);
        self.pos.push(pos);
        self.vel.push(vel);
        self.omega.push(omega);
        self.radius.push(radius);
        self.inv_mass.push(1.0 / mass);
        self.inv_inertia
            .push(1.0 / (inertia_factor * mass * radius * radius));
        self.material.push(material);
        self.force.push(Vector::ZERO);
        self.torque.push(AngVector::default());
        if !self.ledger.is_empty() {
            self.ledger.push(Default::default());
        }
    }

    /// Mass of particle `i`.
    #[inline]
    pub fn mass(&self, i: usize) -> f64 {
        1.0 / self.inv_mass[i]
    }

    /// Reorders every field by `perm` (new index k holds old particle `perm[k]`).
    pub fn permute(&mut self, perm: &[u32]) {
        fn apply<T: Copy>(v: &mut Vec<T>, perm: &[u32]) {
            let old = std::mem::take(v);
            *v = perm.iter().map(|&p| old[p as usize]).collect();
        }
        apply(&mut self.id, perm);
        apply(&mut self.pos, perm);
        apply(&mut self.vel, perm);
        apply(&mut self.omega, perm);
        apply(&mut self.radius, perm);
        apply(&mut self.inv_mass, perm);
        apply(&mut self.inv_inertia, perm);
        apply(&mut self.material, perm);
        apply(&mut self.force, perm);
        apply(&mut self.torque, perm);
        if !self.ledger.is_empty() {
            permute_in_place(&mut self.ledger, perm);
        }
    }

    /// Largest radius (0 when empty).
    pub fn max_radius(&self) -> f64 {
        self.radius.iter().copied().fold(0.0, f64::max)
    }
}

/// Reorders `v` by `perm` (new index k holds old element `perm[k]`) along its cycles,
/// without a second copy: the ledger's rows are the largest field, and a fresh one at
/// every rebuild costs the kernel its pages again (measured: +1.1 s of system time on
/// `ring_small_elastic`, 995 rebuilds of 17 k rows).
fn permute_in_place<T: Copy>(v: &mut [T], perm: &[u32]) {
    let mut done = vec![false; v.len()];
    for start in 0..v.len() {
        if done[start] {
            continue;
        }
        let first = v[start];
        let mut k = start;
        loop {
            done[k] = true;
            let from = perm[k] as usize;
            if from == start {
                v[k] = first;
                break;
            }
            v[k] = v[from];
            k = from;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::permute_in_place;

    #[test]
    fn a_permutation_in_place_is_the_copying_one() {
        let n = 1000u32;
        // A permutation of several cycles (and fixed points) from an LCG.
        let mut perm: Vec<u32> = (0..n).collect();
        let mut x = 12345u64;
        for i in (1..n as usize).rev() {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            perm.swap(i, (x >> 33) as usize % (i + 1));
        }
        let old: Vec<u64> = (0..n as u64).map(|k| k * 7 + 3).collect();
        let want: Vec<u64> = perm.iter().map(|&p| old[p as usize]).collect();
        let mut got = old.clone();
        permute_in_place(&mut got, &perm);
        assert_eq!(got, want);
    }
}
