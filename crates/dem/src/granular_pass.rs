//! The pair pass under the granular law ([`crate::granular`]): every listed pair that
//! touches is evaluated with [`respond`] and its forces and torques applied, in the same
//! fixed chunks as the linear law's pass ([`crate::forces`]), so the sums are the same
//! for any thread count.
//!
//! Unlike the linear law, the two bodies' torques differ by more than their radii (the
//! arms are R − δ/2 and rolling and twisting add a couple), so an entry whose partner
//! lies in another chunk leaves the partner's torque divided by its radius in `ftan`,
//! which `walls_gather_kick` multiplies back.

use crate::contact::PairTable;
use crate::granular::{respond, Contact, GranularParams, WIDTH};
use crate::math::{AngVector, Vector};
use crate::neighbours::{ContactList, GranularHistory};
use crate::particles::Particles;
use crate::setup::Setup;
use crate::CHUNK;
use rayon::prelude::*;

/// The slices one task owns.
struct Chunk<'a> {
    range: std::ops::Range<usize>,
    history: &'a mut [GranularHistory],
    fpair: &'a mut [Vector],
    ftan: &'a mut [AngVector],
    force: &'a mut [Vector],
    torque: &'a mut [AngVector],
}

/// Evaluates every listed pair under `table`'s laws, advancing the histories by `dt`
/// (none when `dt` is 0: the evaluation of a set-up, as LAMMPS's).
pub fn pair_contacts(
    setup: &Setup,
    table: &PairTable<GranularParams>,
    p: &mut Particles,
    list: &mut ContactList,
    dt: f64,
) {
    let n = p.len();
    list.history.resize(list.nbr.len(), [0.0; WIDTH]);
    let row = &list.row;
    let mut jobs = Vec::with_capacity(n.div_ceil(CHUNK));
    let (mut history, mut fpair, mut ftan) = (
        &mut list.history[..],
        &mut list.fpair[..],
        &mut list.ftan[..],
    );
    let (pos, vel, omega, radius, inv_mass, material) = (
        &p.pos,
        &p.vel,
        &p.omega,
        &p.radius,
        &p.inv_mass,
        &p.material,
    );
    let mut force = p.force.chunks_mut(CHUNK);
    let mut torque = p.torque.chunks_mut(CHUNK);
    for c in 0..n.div_ceil(CHUNK) {
        let range = c * CHUNK..((c + 1) * CHUNK).min(n);
        let len = (row[range.end] - row[range.start]) as usize;
        let (h, h_rest) = history.split_at_mut(len);
        let (f, f_rest) = fpair.split_at_mut(len);
        let (t, t_rest) = ftan.split_at_mut(len);
        jobs.push(Chunk {
            range,
            history: h,
            fpair: f,
            ftan: t,
            force: force.next().unwrap_or_default(),
            torque: torque.next().unwrap_or_default(),
        });
        (history, fpair, ftan) = (h_rest, f_rest, t_rest);
    }
    let (owner, nbr) = (&list.owner, &list.nbr);
    jobs.into_par_iter().for_each(|c| {
        let (first, end) = (c.range.start, c.range.end);
        let base = row[first] as usize;
        c.force.fill(Vector::ZERO);
        c.torque.fill(AngVector::default());
        for k in 0..c.history.len() {
            let (i, j) = (owner[base + k] as usize, nbr[base + k] as usize);
            if j >= end {
                c.fpair[k] = Vector::ZERO;
                c.ftan[k] = AngVector::default();
            }
            let d = setup.domain.min_image(pos[j] - pos[i]);
            let (ri, rj) = (radius[i], radius[j]);
            let rsum = ri + rj;
            let dist2 = d.length_squared();
            if !(dist2 < rsum * rsum && dist2 > 0.0) {
                c.history[k] = [0.0; WIDTH];
                continue;
            }
            let dist = dist2.sqrt();
            let contact = Contact {
                n: d / dist,
                overlap: rsum - dist,
                r_eff: ri * rj / rsum,
                m_eff: 1.0 / (inv_mass[i] + inv_mass[j]),
                v: vel[i] - vel[j],
                spin: ri * omega[i] + rj * omega[j],
                w_rel: omega[i] - omega[j],
            };
            let law = table.get(material[i] as usize, material[j] as usize);
            let r = respond(law, &contact, &mut c.history[k], dt, dt > 0.0);
            let half = 0.5 * contact.overlap;
            c.force[i - first] += r.force;
            c.torque[i - first] += (ri - half) * r.moment + r.couple;
            let tj = (rj - half) * r.moment - r.couple;
            if j < end {
                c.force[j - first] -= r.force;
                c.torque[j - first] += tj;
            } else {
                c.fpair[k] = r.force;
                c.ftan[k] = tj * (1.0 / rj);
            }
        }
    });
}
