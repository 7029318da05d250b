//! The particle and list fields both pair passes ([`crate::forces`] for the linear law,
//! [`crate::granular_pass`] for the granular one) read, in one struct.

use crate::math::{AngVector, Vector};

/// What a pair pass reads of the particles and the list: borrowed field by field (by
/// [`pass_fields!`]) so that a chunk's own slices, its forces, torques and springs, can
/// be borrowed mutably beside it.
pub(crate) struct PassFields<'a> {
    /// Each particle's first entry (CSR rows of the list).
    pub row: &'a [u32],
    /// Each entry's partner.
    pub nbr: &'a [u32],
    /// Each entry's owner.
    pub owner: &'a [u32],
    /// The particles' positions.
    pub pos: &'a [Vector],
    /// Velocities.
    pub vel: &'a [Vector],
    /// Angular velocities.
    pub omega: &'a [AngVector],
    /// Radii.
    pub radius: &'a [f64],
    /// Inverse masses.
    pub inv_mass: &'a [f64],
    /// Materials.
    pub material: &'a [u16],
}

/// [`PassFields`] of the particles `$p` and the list `$list`, one field at a time (a
/// function taking `&Particles` would hold all of them).
macro_rules! pass_fields {
    ($p:expr, $list:expr) => {
        $crate::pass_fields::PassFields {
            row: &$list.row,
            nbr: &$list.nbr,
            owner: &$list.owner,
            pos: &$p.pos,
            vel: &$p.vel,
            omega: &$p.omega,
            radius: &$p.radius,
            inv_mass: &$p.inv_mass,
            material: &$p.material,
        }
    };
}
pub(crate) use pass_fields;
