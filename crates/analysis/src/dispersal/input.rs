//! What the dispersal analysis reads: plain slices of particle data and, for stress,
//! the contact forces. Any engine (DEM, FEM–DEM) or a frame file can fill them.

use glam::{DMat2, DVec2};

pub use grains_core::input::InputError;

/// Checks that `v` is finite and positive.
pub(crate) fn positive(key: &str, v: f64) -> Result<f64, InputError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(InputError::new(key, v, "must be a finite number > 0"))
    }
}

/// Checks that the count `v` is at least `min`.
pub(crate) fn at_least(key: &str, v: usize, min: usize) -> Result<usize, InputError> {
    if v >= min {
        Ok(v)
    } else {
        Err(InputError::new(key, v, format!("must be at least {min}")))
    }
}

/// The disks of one frame, one slice per field (all the same length). SI units; the
/// masses are per unit thickness, like everything else in the 2D engines.
#[derive(Clone, Copy, Debug)]
pub struct ParticleSet<'a> {
    /// Centres (m).
    pub pos: &'a [DVec2],
    /// Velocities (m/s).
    pub vel: &'a [DVec2],
    /// Radii (m).
    pub radius: &'a [f64],
    /// Masses (kg/m).
    pub mass: &'a [f64],
    /// Stable identities, used to follow grains from frame to frame (jets).
    pub id: &'a [u32],
}

impl<'a> ParticleSet<'a> {
    /// Bundles the slices, checking that they have one entry per particle.
    pub fn new(
        pos: &'a [DVec2],
        vel: &'a [DVec2],
        radius: &'a [f64],
        mass: &'a [f64],
        id: &'a [u32],
    ) -> Result<Self, InputError> {
        let n = pos.len();
        for (key, len) in [
            ("particles.vel", vel.len()),
            ("particles.radius", radius.len()),
            ("particles.mass", mass.len()),
            ("particles.id", id.len()),
        ] {
            if len != n {
                return Err(InputError::new(
                    key,
                    format!("{len} entries"),
                    format!("must have one per particle ({n})"),
                ));
            }
        }
        Ok(ParticleSet {
            pos,
            vel,
            radius,
            mass,
            id,
        })
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// True when there are no particles.
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// Total mass (kg/m).
    pub fn total_mass(&self) -> f64 {
        self.mass.iter().sum()
    }
}

/// The particle–particle contacts of one frame: contact `c` joins particles `i[c]` and
/// `j[c]` (indices into the [`ParticleSet`]) and `force[c]` is the force that `j[c]`
/// exerts on `i[c]` (N/m; normal and tangential parts together). A compressive contact
/// therefore has `force · (x_j − x_i) < 0`. Each contact is listed once.
#[derive(Clone, Copy, Debug)]
pub struct Contacts<'a> {
    /// First particle of each contact.
    pub i: &'a [u32],
    /// Second particle of each contact.
    pub j: &'a [u32],
    /// Force on `i` from `j` (N/m).
    pub force: &'a [DVec2],
}

impl<'a> Contacts<'a> {
    /// Bundles the slices, checking their lengths and that every index refers to one of
    /// `n_particles` particles.
    pub fn new(
        i: &'a [u32],
        j: &'a [u32],
        force: &'a [DVec2],
        n_particles: usize,
    ) -> Result<Self, InputError> {
        let n = i.len();
        for (key, len) in [("contacts.j", j.len()), ("contacts.force", force.len())] {
            if len != n {
                return Err(InputError::new(
                    key,
                    format!("{len} entries"),
                    format!("must have one per contact ({n})"),
                ));
            }
        }
        if let Some(&bad) = i.iter().chain(j).find(|&&k| k as usize >= n_particles) {
            return Err(InputError::new(
                "contacts.i/j",
                bad,
                format!("must index one of the {n_particles} particles"),
            ));
        }
        Ok(Contacts { i, j, force })
    }

    /// Number of contacts.
    pub fn len(&self) -> usize {
        self.i.len()
    }

    /// True when there are no contacts.
    pub fn is_empty(&self) -> bool {
        self.i.is_empty()
    }
}

/// Where the stress of Eq. 6 comes from.
#[derive(Clone, Copy, Debug)]
pub enum StressSource<'a> {
    /// Contact forces and branch vectors: each contact's `l ⊗ f` is shared among the
    /// bins its branch vector crosses, in proportion to the length inside each.
    Contacts(Contacts<'a>),
    /// Each particle's own sum `Σ_c a_c ⊗ f_c` over its contacts (N; arm `a_c` from its
    /// centre to the contact point, `f_c` the force on it), counted in its centre's bin.
    /// For frames that store a per-particle stress rather than the contact list.
    Particles(&'a [DMat2]),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_and_indices_are_checked() {
        let p = [DVec2::ZERO; 2];
        let r = [1.0; 2];
        let id = [0u32, 1];
        assert!(ParticleSet::new(&p, &p, &r, &r, &id).is_ok());
        let e = ParticleSet::new(&p, &p[..1], &r, &r, &id).unwrap_err();
        assert_eq!(e.key, "particles.vel");
        assert!(e.to_string().contains("one per particle (2)"), "{e}");
        let f = [DVec2::X];
        assert!(Contacts::new(&[0], &[1], &f, 2).is_ok());
        let e = Contacts::new(&[0], &[2], &f, 2).unwrap_err();
        assert_eq!(e.value, "2");
        assert!(Contacts::new(&[0, 1], &[1], &f, 2).is_err());
        assert!(positive("k", 0.0).is_err());
    }
}
