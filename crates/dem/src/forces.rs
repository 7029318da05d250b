//! The contact law (one function for particle pairs and walls) and the pair pass.

use crate::contact::PairParams;
use crate::neighbours::ContactList;
use crate::particles::Particles;
use crate::setup::Setup;
use crate::CHUNK;
use glam::DVec2;
use rayon::prelude::*;

/// Normal and tangential force magnitudes of one contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactForce {
    /// Normal force (positive pushes the bodies apart).
    pub normal: f64,
    /// Tangential force on body i along t = (−n_y, n_x).
    pub tangential: f64,
}

/// Linear spring-dashpot normal force and incremental tangential spring with a Coulomb
/// cap, for a contact with unit normal `n` (from body i towards body j) and overlap
/// `overlap` > 0.
///
/// `v_rel` is v_i − v_j; `spin` is r_i ω_i + r_j ω_j (the rotational part of the
/// contact points' relative sliding speed, r_j ω_j = 0 for a wall); `shear` is the
/// contact's tangential spring, advanced by v_t·`dt` (pass `dt = 0` to evaluate without
/// advancing it).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn contact_force(
    p: &PairParams,
    m_eff: f64,
    n: DVec2,
    overlap: f64,
    v_rel: DVec2,
    spin: f64,
    shear: &mut f64,
    dt: f64,
) -> ContactForce {
    let t = n.perp();
    let vn = v_rel.dot(n); // > 0 while approaching
    let vt = v_rel.dot(t) + spin;
    let mut fnorm = p.kn * overlap + p.normal_dashpot(m_eff) * vn;
    if p.limit_damping && fnorm < 0.0 {
        fnorm = 0.0;
    }
    let ct = p.gamma_t * m_eff;
    *shear += vt * dt;
    let mut ft = -(p.kt * *shear + ct * vt);
    let cap = p.mu * fnorm.abs();
    if ft.abs() > cap {
        // Slide: the spring is reset so that spring + dashpot sit exactly on the cap
        // (the LAMMPS convention), keeping the history consistent with the force.
        ft = cap.copysign(ft);
        *shear = if p.kt > 0.0 {
            -(ft + ct * vt) / p.kt
        } else {
            0.0
        };
    }
    ContactForce {
        normal: fnorm,
        tangential: ft,
    }
}

/// Evaluates every listed pair: writes each entry's force on its row owner and its
/// tangential force, and advances the tangential springs by `dt` (0 to only evaluate).
pub fn pair_contacts(setup: &Setup, p: &Particles, list: &mut ContactList, dt: f64) {
    let n = p.len();
    let row = &list.row;
    let nbr = &list.nbr;
    // Split the entry arrays at chunk boundaries so each task owns its slice.
    let mut jobs = Vec::with_capacity(n.div_ceil(CHUNK));
    let (mut shear, mut fpair, mut ftan) =
        (&mut list.shear[..], &mut list.fpair[..], &mut list.ftan[..]);
    let mut done = 0usize;
    for c in 0..n.div_ceil(CHUNK) {
        let range = c * CHUNK..((c + 1) * CHUNK).min(n);
        let len = row[range.end] as usize - done;
        let (s, s_rest) = shear.split_at_mut(len);
        let (f, f_rest) = fpair.split_at_mut(len);
        let (t, t_rest) = ftan.split_at_mut(len);
        jobs.push((range, s, f, t));
        shear = s_rest;
        fpair = f_rest;
        ftan = t_rest;
        done += len;
    }
    jobs.into_par_iter()
        .for_each(|(range, shear, fpair, ftan)| {
            let base = row[range.start] as usize;
            for i in range {
                let (pi, ri, vi, wi) = (p.pos[i], p.radius[i], p.vel[i], p.omega[i]);
                let mi = p.material[i] as usize;
                for e in row[i] as usize..row[i + 1] as usize {
                    let j = nbr[e] as usize;
                    let k = e - base;
                    let d = setup.domain.min_image(p.pos[j] - pi);
                    let rsum = ri + p.radius[j];
                    let dist2 = d.length_squared();
                    if dist2 >= rsum * rsum || dist2 == 0.0 {
                        shear[k] = 0.0;
                        fpair[k] = DVec2::ZERO;
                        ftan[k] = 0.0;
                        continue;
                    }
                    let dist = dist2.sqrt();
                    let nrm = d / dist;
                    let params = setup.pairs.get(mi, p.material[j] as usize);
                    let m_eff = 1.0 / (p.inv_mass[i] + p.inv_mass[j]);
                    let spin = ri * wi + p.radius[j] * p.omega[j];
                    let f = contact_force(
                        params,
                        m_eff,
                        nrm,
                        rsum - dist,
                        vi - p.vel[j],
                        spin,
                        &mut shear[k],
                        dt,
                    );
                    fpair[k] = -f.normal * nrm + f.tangential * nrm.perp();
                    ftan[k] = f.tangential;
                }
            }
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coulomb_cap_holds_and_history_matches_force() {
        let p = PairParams {
            kn: 1e4,
            kt: 5e3,
            mu: 0.3,
            by_ratio: true,
            ..Default::default()
        };
        let mut xi = 0.0;
        let f = contact_force(
            &p,
            1.0,
            DVec2::X,
            1e-3,
            DVec2::new(0.0, 1.0),
            0.0,
            &mut xi,
            1e-2,
        );
        assert!((f.normal - 10.0).abs() < 1e-12);
        assert!((f.tangential.abs() - 3.0).abs() < 1e-12);
        assert!((p.kt * xi + f.tangential).abs() < 1e-12);
    }
}
