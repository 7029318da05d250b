//! Each particle's contact stress (Love's average over the particle), for frames and for the
//! coarse-grained stress of the dispersal analysis (xue-2019 Eq. 6). Read-only: the
//! contact forces are evaluated again from the state, springs as stored, not advanced.

use crate::law::{Contact, ContactLaw};
use crate::math::{self, outer, Tangent, Tensor, Vector};
use crate::neighbours::GranularHistory;
use crate::setup::Setup;
use crate::step::State;

/// The force on the first body of a contact between materials `a` and `b` under the
/// set-up's law, and F_n, the history as stored (`shear` under the linear law,
/// `history` under the granular law; copies: nothing is advanced).
fn force_now(
    setup: &Setup,
    (a, b): (usize, usize),
    c: &Contact,
    shear: Tangent,
    history: Option<GranularHistory>,
) -> (Vector, f64) {
    let r = match &setup.granular {
        Some(t) => t
            .get(a, b)
            .respond(c, &mut history.unwrap_or_default(), 0.0),
        None => setup.pairs.get(a, b).respond(c, &mut { shear }, 0.0),
    };
    (r.force, r.normal)
}

/// One touching pair of particles as the contact law sees it now.
#[derive(Clone, Copy, Debug)]
pub struct PairForce {
    /// Storage index of the first particle.
    pub i: usize,
    /// Storage index of the second.
    pub j: usize,
    /// Branch vector from i's centre to j's (minimum image) (m).
    pub branch: Vector,
    /// Unit normal from i towards j.
    pub normal: Vector,
    /// Overlap (m).
    pub overlap: f64,
    /// The force on i (j gets the opposite).
    pub force: Vector,
    /// The normal force F_n (positive pushes apart), damping included.
    pub push: f64,
}

impl PairForce {
    /// The normal part of the force on i, −F_n n.
    pub fn normal_force(&self) -> Vector {
        -self.push * self.normal
    }

    /// The tangential part of the force on i.
    pub fn tangential_force(&self) -> Vector {
        self.force - self.normal_force()
    }
}

/// Calls `f` for each touching pair of particles (walls left out), the force evaluated
/// by the set-up's contact law (the linear law's, or the granular law's) with the
/// present velocities and the stored tangential history, not advanced.
pub fn each_pair_force(setup: &Setup, s: &State, mut f: impl FnMut(PairForce)) {
    let list = &s.contacts;
    let n = s.particles.len();
    if list.row.len() != n + 1 {
        return;
    }
    for i in 0..n {
        for e in list.row[i] as usize..list.row[i + 1] as usize {
            if let Some(c) = pair_force(setup, s, i, e) {
                f(c);
            }
        }
    }
}

/// The pair of list entry `e` in the row of particle `i`, if it touches.
fn pair_force(setup: &Setup, s: &State, i: usize, e: usize) -> Option<PairForce> {
    let p = &s.particles;
    let list = &s.contacts;
    let j = list.nbr[e] as usize;
    let d = setup.domain.min_image(p.pos[j] - p.pos[i]);
    let dist = d.length();
    let overlap = p.radius[i] + p.radius[j] - dist;
    if overlap <= 0.0 || dist == 0.0 {
        return None;
    }
    let nv = d / dist;
    let (mi, mj) = (p.material[i] as usize, p.material[j] as usize);
    let m_eff = 1.0 / (p.inv_mass[i] + p.inv_mass[j]);
    let spin = p.radius[i] * p.omega[i] + p.radius[j] * p.omega[j];
    let c = Contact {
        n: nv,
        overlap,
        r_eff: p.radius[i] * p.radius[j] / (p.radius[i] + p.radius[j]),
        m_eff,
        v: p.vel[i] - p.vel[j],
        spin,
        w_rel: p.omega[i] - p.omega[j],
    };
    let (force, push) = force_now(setup, (mi, mj), &c, list.spring(e), list.granular(e));
    Some(PairForce {
        i,
        j,
        branch: d,
        normal: nv,
        overlap,
        force,
        push,
    })
}

/// Σ a ⊗ f over each particle's pair contacts. With the list's reverse index, each
/// particle adds its row (partners of higher id, ascending) and then its reverse entries
/// (partners of lower id, ascending), as the step adds forces (rule 1 of
/// docs/parallel.md): a function of ids alone, so the same bits whatever the storage
/// order or the rank that holds the particle. A pair is evaluated once from each side.
fn pair_moments(setup: &Setup, s: &State) -> Vec<Tensor> {
    let p = &s.particles;
    let list = &s.contacts;
    let n = p.len();
    let mut sum = vec![Tensor::ZERO; n];
    let indexed = list.row.len() == n + 1
        && list.rev_row.len() == n + 1
        && list.owner.len() == list.nbr.len();
    if !indexed {
        each_pair_force(setup, s, |c| {
            let (i, j, nv, overlap) = (c.i, c.j, c.normal, c.overlap);
            sum[i] += outer((p.radius[i] - 0.5 * overlap) * nv, c.force);
            sum[j] += outer(-(p.radius[j] - 0.5 * overlap) * nv, -c.force);
        });
        return sum;
    }
    for (i, total) in sum.iter_mut().enumerate() {
        for e in list.row[i] as usize..list.row[i + 1] as usize {
            if let Some(c) = pair_force(setup, s, i, e) {
                *total += outer((p.radius[i] - 0.5 * c.overlap) * c.normal, c.force);
            }
        }
        let rev = &list.rev_entry[list.rev_row[i] as usize..list.rev_row[i + 1] as usize];
        for &e in rev {
            let owner = list.owner[e as usize] as usize;
            if let Some(c) = pair_force(setup, s, owner, e as usize) {
                *total += outer(-(p.radius[i] - 0.5 * c.overlap) * c.normal, -c.force);
            }
        }
    }
    sum
}

/// Each particle's contact stress σ_i = (1/V_i) Σ_c a_c ⊗ f_c (Pa, tension positive; V_i
/// the disk's area πr_i² in 2D, the stress per unit thickness, the sphere's volume in 3D): `a_c` from the centre to the middle of the overlap, `f_c` the force
/// on the particle, over its pair and wall contacts. The forces are the contact law's
/// (the linear law's, or the granular law's when the set-up has one)
/// with the present velocities and the stored tangential springs; summed over both
/// particles of a pair the arms add up to the branch vector, so Σ_i V_i σ_i is Σ over
/// contacts of l ⊗ f, the sum of Eq. 6.
pub fn particle_stress(setup: &Setup, s: &State) -> Vec<Tensor> {
    let p = &s.particles;
    let list = &s.contacts;
    let n = p.len();
    let mut sum = pair_moments(setup, s);
    for i in 0..n {
        for o in crate::walls::overlapping_walls(setup, p, i) {
            let c = Contact {
                n: o.touch.normal,
                overlap: o.overlap,
                r_eff: p.radius[i],
                m_eff: p.mass(i),
                v: p.vel[i],
                spin: p.radius[i] * p.omega[i],
                w_rel: p.omega[i],
            };
            let xi = list.wall_shear.get(o.slot).copied().unwrap_or_default();
            let history = list.wall_history.try_get(o.slot);
            let (f, _) = force_now(setup, o.materials, &c, xi, history);
            let arm = (o.touch.distance + 0.5 * o.overlap) * o.touch.normal;
            sum[i] += outer(arm, f);
        }
    }
    sum.iter()
        .zip(&p.radius)
        .map(|(m, r)| *m * (1.0 / math::measure(*r)))
        .collect()
}

#[cfg(all(test, feature = "dim2"))]
mod tests {
    use super::*;
    use crate::contact::ContactModel;
    use crate::domain::Domain;
    use crate::material::Material;
    use crate::particles::Particles;
    use glam::DVec2;

    fn setup(materials: &[Material]) -> Setup {
        let domain = Domain {
            lo: DVec2::splat(-1.0),
            hi: DVec2::splat(1.0),
            periodic: [false, false],
        };
        let model = ContactModel::Material {
            limit_damping: false,
        };
        Setup::new(
            domain,
            materials.to_vec(),
            model,
            Vec::new(),
            DVec2::ZERO,
            1e-3,
        )
        .unwrap()
    }

    /// Two disks pressed together along x at rest: σ_xx of each is −k δ (r − δ/2)/(πr²),
    /// the other components zero, and the area-weighted sum is l ⊗ f.
    #[test]
    fn a_pressed_pair() {
        let mat = Material {
            name: "m".into(),
            density: 1000.0,
            youngs: Some(1e6),
            poisson: Some(0.3),
            friction: Some(0.5),
            restitution: Some(0.5),
            inertia_factor: 0.5,
        };
        let s = setup(std::slice::from_ref(&mat));
        let (r, delta) = (0.01, 1e-4);
        let mut p = Particles::default();
        p.push(DVec2::ZERO, r, 1000.0, 0.5, 0, DVec2::ZERO, 0.0);
        p.push(
            DVec2::new(2.0 * r - delta, 0.0),
            r,
            1000.0,
            0.5,
            0,
            DVec2::ZERO,
            0.0,
        );
        let state = State::new(&s, p);
        let sigma = particle_stress(&s, &state);
        let kn = s.pairs.get(0, 0).kn;
        let want = -kn * delta * (r - 0.5 * delta) / (std::f64::consts::PI * r * r);
        for m in &sigma {
            assert!((m.x_axis.x - want).abs() < 1e-12 * want.abs(), "{m:?}");
            assert_eq!((m.x_axis.y, m.y_axis.x, m.y_axis.y), (0.0, 0.0, 0.0));
        }
        let area = std::f64::consts::PI * r * r;
        let total = (sigma[0] + sigma[1]) * area;
        let branch = 2.0 * r - delta;
        assert!((total.x_axis.x - (-kn * delta * branch)).abs() < 1e-12 * kn * delta * branch);
    }
}
