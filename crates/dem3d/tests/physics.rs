//! The 3D build of the DEM source against closed-form results: a head-on collision of
//! two spheres, an oblique impact on a plane in the sliding regime, a settled column's
//! floor load, conservation of momenta, and bitwise equality across thread counts and
//! through a checkpoint.

use glam::DVec3;
use grains_dem3d::diagnostics::{measure, state_hash};
use grains_dem3d::{
    step, ContactModel, Domain, Material, Particles, Setup, State, Wall, WallShape,
};

const RHO: f64 = 2500.0;

fn glass() -> Material {
    Material {
        name: "glass".into(),
        density: RHO,
        youngs: None,
        poisson: None,
        restitution: None,
        friction: None,
        inertia_factor: 0.4,
    }
}

fn setup(model: ContactModel, walls: Vec<Wall>, gravity: DVec3, periodic: [bool; 3]) -> Setup {
    let domain = Domain {
        lo: DVec3::ZERO,
        hi: DVec3::splat(0.1),
        periodic,
    };
    Setup::new(domain, vec![glass()], model, walls, gravity, 1e-3).unwrap()
}

fn floor() -> Wall {
    Wall {
        name: "floor".into(),
        shape: WallShape::Plane {
            point: [0.0, 0.0, 0.0],
            normal: [0.0, 0.0, 1.0],
        },
        material: None,
        motion: Default::default(),
    }
}

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

fn cloud(n_side: usize, r: f64, jitter: u64) -> Particles {
    let mut p = Particles::default();
    let mut seed = jitter;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let gap = 2.05 * r;
    for k in 0..n_side {
        for j in 0..n_side {
            for i in 0..n_side {
                let x = DVec3::new(
                    0.01 + i as f64 * gap,
                    0.01 + j as f64 * gap,
                    r * 1.1 + k as f64 * gap,
                );
                let v = DVec3::new(next(), next(), next());
                let w = 10.0 * DVec3::new(next(), next(), next());
                let rr = r * (1.0 + 0.1 * next());
                p.push(x, rr, RHO, 0.4, 0, v, w);
            }
        }
    }
    p
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

fn bed() -> (Setup, Particles) {
    let g = DVec3::new(0.0, 0.0, -9.81);
    let mut s = setup(
        ContactModel::hooke_history(2e4, 200.0, 0.5),
        vec![floor()],
        g,
        [true, true, false],
    );
    s.domain.hi = DVec3::new(0.05, 0.05, 0.1);
    // More particles than one chunk, so the chunk borders and the reverse pass count.
    (s, cloud(14, 0.0015, 11))
}

/// `steps` steps of `dt` from `p` on a pool of `threads` threads.
fn run_on(s: &Setup, p: Particles, threads: usize, steps: usize, dt: f64) -> State {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut st = State::new(s, p);
        for _ in 0..steps {
            step(s, &mut st, dt);
        }
        st
    })
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

/// Chung & Ooi (2011) test 1: two glass spheres (E 48 GPa, ν 0.20, ρ 2800 kg/m³, R 10 mm)
/// meet head on at ±10 m/s under Hertz's law without damping. Hertz: with E* = E/(2(1 −
/// ν²)), R* = R/2, m* = m/2 and v = 20 m/s, δ_max = (15 m* v² / (16 E* √R*))^{2/5},
/// F_max = (4/3) E* √R* δ_max^{3/2}, t_c = 2.868 (m*² / (R* E*² v))^{1/5}.
#[test]
fn chung_ooi_test_1_hertz_impact_of_two_spheres() {
    use grains_dem3d::granular::{Damping, GranularParams, Normal, Tangential};
    use grains_dem3d::PairTable;
    let (e, nu, rho, r, v) = (48e9, 0.20, 2800.0, 0.01, 10.0);
    let law = GranularParams::lammps(
        Normal::HertzMaterial,
        e,
        Damping::Velocity,
        0.0,
        nu,
        Tangential::Mindlin,
        None,
        1.0,
        0.35,
    );
    let mut s = setup(
        ContactModel::hooke_history(1.0, 0.0, 0.0),
        vec![],
        DVec3::ZERO,
        [false; 3],
    );
    s.granular = Some(PairTable::from_fn(1, |_, _| law));
    let mut p = Particles::default();
    p.push(
        DVec3::new(0.0389, 0.05, 0.05),
        r,
        rho,
        0.4,
        0,
        DVec3::X * v,
        DVec3::ZERO,
    );
    p.push(
        DVec3::new(0.0611, 0.05, 0.05),
        r,
        rho,
        0.4,
        0,
        -DVec3::X * v,
        DVec3::ZERO,
    );
    let m_eff = 0.5 * p.mass(0);
    let mut st = State::new(&s, p);
    let (mut overlap, mut force, mut t_in, mut t_out) = (0.0f64, 0.0f64, None, None);
    for _ in 0..200_000 {
        step(&s, &mut st, 1e-9);
        let d = st.particles.pos[0].distance(st.particles.pos[1]);
        overlap = overlap.max(2.0 * r - d);
        force = force.max(st.particles.force[0].length());
        if d < 2.0 * r && t_in.is_none() {
            t_in = Some(st.time);
        }
        if d >= 2.0 * r && t_in.is_some() && t_out.is_none() {
            t_out = Some(st.time);
            break;
        }
    }
    let (e_star, r_star, vrel) = (e / (2.0 * (1.0 - nu * nu)), 0.5 * r, 2.0 * v);
    let delta = (15.0 * m_eff * vrel * vrel / (16.0 * e_star * r_star.sqrt())).powf(0.4);
    let f_max = 4.0 / 3.0 * e_star * r_star.sqrt() * delta.powf(1.5);
    let t_c = 2.868 * (m_eff * m_eff / (r_star * e_star * e_star * vrel)).powf(0.2);
    let tc = t_out.unwrap() - t_in.unwrap();
    for (what, got, want) in [
        ("max overlap", overlap, delta),
        ("peak force", force, f_max),
        ("contact time", tc, t_c),
    ] {
        assert!(
            (got / want - 1.0).abs() < 0.01,
            "{what}: {got:e} against {want:e}"
        );
    }
    // Undamped: the spheres leave at the speed they came.
    let out = st.particles.vel[1].x - st.particles.vel[0].x;
    assert!((out / vrel - 1.0).abs() < 1e-3, "{out}");
}

/// The granular law on a bed: the same state on 1, 2 and 3 threads, and through a
/// checkpoint.
#[test]
fn granular_bed_is_bitwise_on_threads_and_through_a_checkpoint() {
    use grains_dem3d::granular::{Damping, GranularParams, Normal, Rolling, Tangential};
    let law = GranularParams {
        rolling: Some(Rolling {
            kr: 50.0,
            gamma_r: 0.01,
            mu_r: 0.1,
        }),
        twisting: true,
        ..GranularParams::lammps(
            Normal::HertzMaterial,
            5e7,
            Damping::Tsuji,
            0.5,
            0.3,
            Tangential::Mindlin,
            None,
            1.0,
            0.5,
        )
    };
    granular_bed_is_bitwise(law);
}

/// The granular `law` on a bed: the same state on 1, 2 and 3 threads (one takes the
/// pass and the gather in one sweep, `wavefront`; two and three in two phases), and
/// through a checkpoint.
fn granular_bed_is_bitwise(law: grains_dem3d::granular::GranularParams) {
    use grains_dem3d::PairTable;
    let granular_bed = || {
        let (mut s, p) = bed();
        s.granular = Some(PairTable::from_fn(1, |_, _| law));
        (s, p)
    };
    let run = |threads: usize, steps: usize| {
        let (s, p) = granular_bed();
        run_on(&s, p, threads, steps, 1e-5)
    };
    let one = run(1, 1200);
    assert!((0..one.contacts.len())
        .filter_map(|e| one.contacts.granular(e))
        .any(|h| h.iter().any(|&x| x != 0.0)));
    assert!(measure(&granular_bed().0, &one).elastic > 0.0);
    let hash = state_hash(&one);
    assert_eq!(hash, state_hash(&run(2, 1200)));
    assert_eq!(hash, state_hash(&run(3, 1200)));
    let (s, _) = granular_bed();
    let mut st = run(1, 500);
    let mut bytes = Vec::new();
    grains_dem3d::checkpoint::write(&st, &mut bytes).unwrap();
    let mut back = grains_dem3d::checkpoint::read(&mut bytes.as_slice(), 1 << 20).unwrap();
    for _ in 0..700 {
        step(&s, &mut st, 1e-5);
        step(&s, &mut back, 1e-5);
    }
    assert_eq!(hash, state_hash(&st));
    assert_eq!(hash, state_hash(&back));
}

/// The alumina sphere of Chung & Ooi (2011) (E 380 GPa, ν 0.23, ρ 4000 kg/m³, R 2.5 mm,
/// μ 0.092) moving at `v` just above a plane 1000 times stiffer (as YADE's scripts of
/// these tests make the rigid wall), under Hertz–Mindlin; undamped unless a restitution
/// `e` is given (with that damping). Returns the set-up, the sphere and the pair's law.
fn alumina(
    e: Option<(grains_dem3d::granular::Damping, f64)>,
    v: DVec3,
) -> (Setup, Particles, grains_dem3d::granular::GranularParams) {
    use grains_dem3d::granular::{Damping, GranularParams, Normal, Tangential};
    use grains_dem3d::PairTable;
    let (youngs, nu, rho, r, mu) = (380e9, 0.23, 4000.0, 0.0025, 0.092);
    let (damping, damp) = e.unwrap_or((Damping::Velocity, 0.0));
    let like = |y: f64| {
        GranularParams::lammps(
            Normal::HertzMaterial,
            y,
            damping,
            damp,
            nu,
            Tangential::Mindlin,
            None,
            1.0,
            mu,
        )
    };
    let (sphere, wall) = (like(youngs), like(1000.0 * youngs));
    let pair = GranularParams {
        // Both like pairs share e, so the pair's α is theirs (a geometric mean of α's is
        // not the α of the mean e).
        damp: sphere.damp,
        ..GranularParams::mixed(&sphere, &wall, [youngs, 1000.0 * youngs], [nu, nu])
    };
    let mut s = setup(
        ContactModel::hooke_history(1.0, 0.0, 0.0),
        vec![floor()],
        DVec3::ZERO,
        [false; 3],
    );
    s.walls[0].material = Some(1);
    s.materials.push(glass());
    s.pairs = PairTable::new(&s.model, &s.materials);
    s.granular = Some(PairTable::from_fn(2, |a, b| match (a, b) {
        (0, 0) => sphere,
        (1, 1) => wall,
        _ => pair,
    }));
    let mut p = Particles::default();
    p.push(
        DVec3::new(0.05, 0.05, r + 1e-6),
        r,
        rho,
        0.4,
        0,
        v,
        DVec3::ZERO,
    );
    (s, p, pair)
}

/// Runs the sphere until it leaves the plane: its state then, and the largest overlap,
/// the peak force and the contact time.
fn bounce(s: &Setup, p: Particles, dt: f64) -> (State, f64, f64, f64) {
    let r = p.radius[0];
    let mut st = State::new(s, p);
    let (mut overlap, mut force, mut t_in) = (0.0f64, 0.0f64, None);
    for _ in 0..2_000_000 {
        step(s, &mut st, dt);
        let gap = st.particles.pos[0].z - r;
        overlap = overlap.max(-gap);
        force = force.max(st.particles.force[0].length());
        if gap < 0.0 && t_in.is_none() {
            t_in = Some(st.time);
        }
        if let (true, Some(t0)) = (gap >= 0.0, t_in) {
            let t = st.time - t0;
            return (st, overlap, force, t);
        }
    }
    panic!("the sphere did not leave the plane");
}

/// Chung & Ooi test 2: the alumina sphere hits the plane head on at 0.2 m/s; Hertz with
/// R* = R and m* = m gives its largest overlap, peak force and contact time (the
/// formulas of test 1, E* the pair's).
#[test]
fn chung_ooi_test_2_hertz_impact_on_a_plane() {
    let v = 0.2;
    let (s, p, pair) = alumina(None, -v * DVec3::Z);
    let (r, m) = (p.radius[0], p.mass(0));
    let (_, got_delta, got_f, got_t) = bounce(&s, p, 1e-9);
    let e_star = 0.75 * pair.kn;
    let delta = (15.0 * m * v * v / (16.0 * e_star * r.sqrt())).powf(0.4);
    let f_max = 4.0 / 3.0 * e_star * r.sqrt() * delta.powf(1.5);
    let t_c = 2.868 * (m * m / (r * e_star * e_star * v)).powf(0.2);
    for (what, got, want) in [
        ("max overlap", got_delta, delta),
        ("peak force", got_f, f_max),
        ("contact time", got_t, t_c),
    ] {
        assert!(
            (got / want - 1.0).abs() < 0.01,
            "{what}: {got:e} against {want:e}"
        );
    }
}

/// Chung & Ooi test 4: the alumina sphere hits the plane at 3.9 m/s, 60° from the
/// normal, steeper than the sliding angle (tan θ > (1 + 1/K) μ (1 + e), 32.8° here): the
/// rigid-body limit gives its spin ω R = μ (1 + e) v_n / K and tangential speed
/// v_t − μ (1 + e) v_n, with K = 2/5 and e = 1 (undamped).
#[test]
fn chung_ooi_test_4_oblique_impact_above_the_sliding_angle() {
    let (speed, theta) = (3.9, 60f64.to_radians());
    let (vt, vn) = (speed * theta.sin(), speed * theta.cos());
    let (s, p, _) = alumina(None, DVec3::new(vt, 0.0, -vn));
    let r = p.radius[0];
    let (st, _, _, _) = bounce(&s, p, 1e-9);
    let (v, w) = (st.particles.vel[0], st.particles.omega[0]);
    let e = v.z / vn;
    let impulse = 0.092 * (1.0 + e) * vn;
    let (spin, want_spin) = (w.y * r, impulse / 0.4);
    assert!(
        (spin / want_spin - 1.0).abs() < 0.01,
        "ωR {spin} against {want_spin}"
    );
    assert!(
        (v.x / (vt - impulse) - 1.0).abs() < 0.01,
        "v_t {} against {}",
        v.x,
        vt - impulse
    );
}

/// Chung & Ooi test 3: the alumina sphere hits the plane head on at 3.9 m/s with a target
/// restitution e; Tsuji's dashpot with α solved from the Hertz collision
/// (`damping = "restitution"`) rebounds at e within 0.1 % (LAMMPS's `tsuji` fit gives
/// 0.440, 0.616, 0.778, 0.928 here).
#[test]
fn chung_ooi_test_3_restitution_with_the_solved_damping() {
    use grains_dem3d::granular::Damping;
    for e in [0.3, 0.5, 0.7, 0.9] {
        let v = 3.9;
        let (s, p, _) = alumina(Some((Damping::Restitution, e)), -v * DVec3::Z);
        let (st, _, _, _) = bounce(&s, p, 2e-9);
        let got = st.particles.vel[0].z / v;
        assert!((got / e - 1.0).abs() < 1e-3, "e {got} against {e}");
    }
}

/// The plain Hertz–Mindlin law (no rolling, twisting or rescaling: the blocked pass of
/// `granular_pass`) on a bed: the same state on 1, 2 and 3 threads, and through a
/// checkpoint.
#[test]
fn plain_granular_bed_is_bitwise_on_threads_and_through_a_checkpoint() {
    use grains_dem3d::granular::{Damping, GranularParams, Normal, Tangential};
    let law = GranularParams::lammps(
        Normal::HertzMaterial,
        5e7,
        Damping::Tsuji,
        0.5,
        0.3,
        Tangential::Mindlin,
        None,
        1.0,
        0.5,
    );
    granular_bed_is_bitwise(law);
}
