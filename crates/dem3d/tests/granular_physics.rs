//! The 3D build of the DEM source under the granular law (Hertz–Mindlin, Tsuji damping,
//! rolling and twisting resistance): Chung & Ooi's (2011) impact tests against Hertz's
//! closed forms and the rigid-body limit, and bitwise equality across thread counts and
//! through a checkpoint.

mod common;

use common::{bed, floor, glass, run_on, setup};
use glam::DVec3;
use grains_dem3d::diagnostics::{measure, state_hash};
use grains_dem3d::{step, ContactModel, Particles, Setup, State};

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
    use grains_dem3d::granular::{GranularParams, Rolling};
    let law = GranularParams {
        rolling: Some(Rolling {
            kr: 50.0,
            gamma_r: 0.01,
            mu_r: 0.1,
        }),
        twisting: true,
        ..bed_law()
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
    granular_bed_is_bitwise(bed_law());
}

/// The bed's Hertz–Mindlin–Tsuji law (E 50 MPa, e 0.5, ν 0.3, μ 0.5), on which the
/// bitwise tests add rolling and twisting or not.
fn bed_law() -> grains_dem3d::granular::GranularParams {
    use grains_dem3d::granular::{Damping, GranularParams, Normal, Tangential};
    GranularParams::lammps(
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
}
