//! The 3D build of the DEM source under the linear law against closed-form results: a
//! head-on collision of two spheres, an oblique impact on a plane in the sliding regime,
//! a settled column's floor load, conservation of momenta, and bitwise equality across
//! thread counts and through a checkpoint. The granular (Hertz–Mindlin) law's tests are
//! in `granular_physics.rs`.

mod common;

use common::{bed, cloud, floor, glass, run_on, setup, RHO};
use glam::DVec3;
use grains_dem3d::diagnostics::{measure, state_hash};
use grains_dem3d::{step, ContactModel, Domain, Particles, Setup, State};

#[test]
fn a_sphere_has_the_mass_and_inertia_of_a_ball() {
    let mut p = Particles::default();
    p.push(DVec3::ZERO, 0.01, RHO, 0.4, 0, DVec3::ZERO, DVec3::ZERO);
    let m = RHO * 4.0 / 3.0 * std::f64::consts::PI * 1e-6;
    assert!((p.mass(0) - m).abs() < 1e-15 * m);
    assert!((1.0 / p.inv_inertia[0] - 0.4 * m * 1e-4).abs() < 1e-15 * m * 1e-4);
}

#[test]
fn head_on_restitution_and_contact_time_of_the_linear_law() {
    let (kn, gamma_n) = (1e5, 40.0);
    let s = setup(
        ContactModel::hooke_history(kn, gamma_n, 0.0),
        vec![],
        DVec3::ZERO,
        [false; 3],
    );
    let r = 0.005;
    let mut p = Particles::default();
    // Along a diagonal, so every axis takes part.
    let u = DVec3::new(1.0, 2.0, 2.0) / 3.0;
    let c = DVec3::splat(0.05);
    p.push(c - 0.0102 * u, r, RHO, 0.4, 0, u, DVec3::ZERO);
    p.push(c + 0.0102 * u, r, RHO, 0.4, 0, -u, DVec3::ZERO);
    let m_eff = 0.5 * p.mass(0);
    let mut st = State::new(&s, p);
    let (mut t_in, mut t_out) = (None, None);
    for _ in 0..40_000 {
        step(&s, &mut st, 1e-6);
        let touching = st.particles.pos[0].distance(st.particles.pos[1]) < 2.0 * r;
        if touching && t_in.is_none() {
            t_in = Some(st.time);
        }
        if !touching && t_in.is_some() && t_out.is_none() {
            t_out = Some(st.time);
        }
    }
    let v = st.particles.vel[1] - st.particles.vel[0];
    let e = v.dot(u) / 2.0;
    let pair = s.pairs.get(0, 0);
    let (want_e, want_t) = (pair.restitution(m_eff), pair.contact_time(m_eff));
    assert!((e - want_e).abs() < 2e-3, "e {e} against {want_e}");
    let tc = t_out.unwrap() - t_in.unwrap();
    assert!(
        (tc - want_t).abs() < 2e-6 + 0.01 * want_t,
        "{tc} against {want_t}"
    );
    // Straight on: no sliding, no spin, and the relative motion stays on the line.
    for w in &st.particles.omega {
        assert!(w.length() < 1e-9, "{w}");
    }
    assert!(v.cross(u).length() < 1e-9 * v.length(), "{v}");
}

/// A sphere hits a plane obliquely, steeply enough to slide throughout: the rigid-body
/// limit gives its spin ω R = μ (1 + e) v_n / K and tangential speed v_t − μ(1 + e)v_n.
#[test]
fn oblique_impact_on_a_plane_spins_the_sphere_as_the_rigid_body_limit() {
    let mu = 0.1;
    let s = setup(
        ContactModel::hooke_history(1e6, 0.0, mu),
        vec![floor()],
        DVec3::ZERO,
        [false; 3],
    );
    let r = 0.005;
    let (vt, vn) = (2.0, 1.0);
    let mut p = Particles::default();
    // Moving along +x and +y at once, down onto the floor.
    let dir = DVec3::new(0.6, 0.8, 0.0);
    p.push(
        DVec3::new(0.05, 0.05, r + 1e-4),
        r,
        RHO,
        0.4,
        0,
        vt * dir - vn * DVec3::Z,
        DVec3::ZERO,
    );
    let mut st = State::new(&s, p);
    for _ in 0..20_000 {
        step(&s, &mut st, 2e-7);
    }
    let v = st.particles.vel[0];
    let w = st.particles.omega[0];
    assert!(v.z > 0.0, "it bounced: {v}");
    let e = v.z / vn;
    // Undamped: e = 1 up to the integrator's O(Δt²).
    assert!((e - 1.0).abs() < 1e-4, "undamped: e = {e}");
    let impulse = mu * (1.0 + e) * vn;
    // Rolling without slipping on +x needs ω_y = +v/R: the friction spins it that way.
    let axis = DVec3::Z.cross(dir);
    let spin = w.dot(axis) * r;
    let want_spin = impulse / 0.4;
    assert!(
        (spin - want_spin).abs() < 0.01 * want_spin,
        "ωR {spin} against {want_spin}"
    );
    assert!(
        (w - w.dot(axis) * axis).length() < 1e-9 * w.length(),
        "spin axis {w}"
    );
    let v_t = v.dot(dir);
    let want_vt = vt - impulse;
    assert!(
        (v_t - want_vt).abs() < 0.01 * want_vt,
        "v_t {v_t} against {want_vt}"
    );
    assert!(
        (v - v.dot(dir) * dir - v.z * DVec3::Z).length() < 1e-9,
        "{v}"
    );
}

/// Linear momentum is kept exactly. Angular momentum is kept only without friction: the
/// law puts the tangential force at r_i and r_j from the centres (LAMMPS
/// `gran/hooke/history`), which add up to the distance plus the overlap, so a sliding
/// contact exerts a couple δ n × F_t on the pair.
#[test]
fn a_free_cloud_keeps_its_momenta() {
    for mu in [0.0, 0.5] {
        let s = setup(
            ContactModel::hooke_history(1e5, 20.0, mu),
            vec![],
            DVec3::ZERO,
            [false; 3],
        );
        let mut st = State::new(&s, cloud(5, 0.002, 7));
        let moments = |st: &State| {
            let p = &st.particles;
            let (mut lin, mut ang) = (DVec3::ZERO, DVec3::ZERO);
            for i in 0..p.len() {
                let m = p.mass(i);
                lin += m * p.vel[i];
                ang += m * p.pos[i].cross(p.vel[i]) + p.omega[i] / p.inv_inertia[i];
            }
            (lin, ang)
        };
        let (l0, a0) = moments(&st);
        let mut contacts = 0;
        for _ in 0..3000 {
            step(&s, &mut st, 1e-5);
            contacts += measure(&s, &st).pair_contacts;
        }
        let (l1, a1) = moments(&st);
        assert!(contacts > 100, "{contacts}");
        assert!((l1 - l0).length() < 1e-12 * l0.length(), "{l0} → {l1}");
        if mu == 0.0 {
            assert!((a1 - a0).length() < 1e-12 * a0.length(), "{a0} → {a1}");
        }
    }
}

/// Spheres poured into a box periodic in x and y come to rest on the floor, which then
/// carries their weight.
#[test]
fn a_settled_column_rests_its_weight_on_the_floor() {
    let g = DVec3::new(0.0, 0.0, -9.81);
    let mut s = setup(
        ContactModel::hooke_history(2e4, 200.0, 0.5),
        vec![floor()],
        g,
        [true, true, false],
    );
    s.domain.hi = DVec3::new(0.03, 0.03, 0.1);
    let mut st = State::new(&s, cloud(6, 0.002, 3));
    for _ in 0..60_000 {
        step(&s, &mut st, 2e-5);
    }
    let p = &st.particles;
    let weight: f64 = (0..p.len()).map(|i| p.mass(i) * 9.81).sum();
    let load = st.wall_loads[0].force;
    let d = measure(&s, &st);
    assert!(d.kinetic() < 1e-9 * weight, "still moving: {}", d.kinetic());
    assert!(
        (-load.z / weight - 1.0).abs() < 0.005,
        "{load} against {weight}"
    );
}

fn run(threads: usize, steps: usize) -> State {
    let (s, p) = bed();
    run_on(&s, p, threads, steps, 2e-5)
}

#[test]
fn bitwise_identical_for_1_2_3_threads() {
    let one = state_hash(&run(1, 1500));
    assert_eq!(one, state_hash(&run(2, 1500)));
    assert_eq!(one, state_hash(&run(3, 1500)));
}

#[test]
fn checkpoint_and_resume_is_bitwise_identical() {
    let (s, p) = bed();
    let mut st = State::new(&s, p);
    for _ in 0..700 {
        step(&s, &mut st, 2e-5);
    }
    let mut bytes = Vec::new();
    grains_dem3d::checkpoint::write(&st, &mut bytes).unwrap();
    let mut back = grains_dem3d::checkpoint::read(&mut bytes.as_slice(), 1 << 20).unwrap();
    grains_dem3d::checkpoint::fits(&back, &s).unwrap();
    for _ in 0..800 {
        step(&s, &mut st, 2e-5);
        step(&s, &mut back, 2e-5);
    }
    assert!(st.contacts.shear.iter().any(|x| x.length() > 0.0));
    assert_eq!(state_hash(&st), state_hash(&back));
}

#[test]
fn the_material_route_is_refused_in_3d() {
    let domain = Domain {
        lo: DVec3::ZERO,
        hi: DVec3::ONE,
        periodic: [false; 3],
    };
    let err = Setup::new(
        domain,
        vec![glass()],
        ContactModel::default(),
        vec![],
        DVec3::ZERO,
        1e-3,
    )
    .unwrap_err();
    assert!(err.to_string().contains("contact.model"), "{err}");
}

/// A sheared contact whose row owner changes at a rebuild (the pair crosses a cell row,
/// so the cell sort puts the other particle first) keeps its spring as seen from the new
/// owner: the run ends as the same run shifted so that no owner changes.
#[test]
fn a_spring_survives_a_change_of_row_owner() {
    let run = |lift: f64| {
        let mut s = setup(
            ContactModel::hooke_history(1e5, 0.0, 0.8),
            vec![],
            DVec3::ZERO,
            [false; 3],
        );
        // Cells 0.01001 wide; rebuilt every few steps.
        s.skin = 1e-5;
        let r = 0.005;
        let angle = -20f64.to_radians();
        let d = 0.0098 * DVec3::new(angle.cos(), angle.sin(), 0.0);
        let left = DVec3::new(0.05, 0.05 - d.y + lift, 0.05);
        let mut p = Particles::default();
        let common = DVec3::new(0.0, 2.0, 0.0);
        let slide = DVec3::new(0.05, 0.0, 0.2);
        p.push(left, r, RHO, 0.4, 0, common + slide, DVec3::ZERO);
        p.push(left + d, r, RHO, 0.4, 0, common - slide, DVec3::ZERO);
        let mut st = State::new(&s, p);
        let first_owner = st.particles.id[0];
        let mut owners = std::collections::BTreeSet::new();
        for _ in 0..400 {
            step(&s, &mut st, 1e-6);
            if !st.contacts.is_empty() && st.contacts.shear.iter().any(|x| x.length() > 0.0) {
                owners.insert(st.particles.id[0]);
            }
        }
        owners.insert(first_owner);
        let by_id = |k: u32| st.particles.id.iter().position(|&i| i == k).unwrap();
        let (a, b) = (by_id(0), by_id(1));
        let p = &st.particles;
        (owners.len(), [p.vel[a], p.vel[b], p.omega[a], p.omega[b]])
    };
    let (changed, a) = run(0.0);
    let (kept, b) = run(0.004);
    assert_eq!(
        (changed, kept),
        (2, 1),
        "the owner should change in the first run only"
    );
    for (x, y) in a.iter().zip(&b) {
        assert!(
            (*x - *y).length() < 1e-9 * (1.0 + y.length()),
            "{x} against {y}"
        );
    }
    assert!(
        a[2].length() > 1.0,
        "the contact spun the spheres: {}",
        a[2]
    );
}
