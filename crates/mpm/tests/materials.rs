//! Engine-level checks of the materials with memory and of thermal loading: a J2 block
//! in homogeneous simple shear between rigid plates, Maxwell relaxation under held
//! shear, and the free thermal expansion of a disk.

mod common;

use common::*;
use glam::DVec2;
use grains_mpm::*;

const K: f64 = 1.0;
const G: f64 = 0.5;

/// Block [0, L] × [0, 1] (body 0) between a fixed bottom plate (body 1) and a top plate
/// (body 2) moving at `v_top`, both bonded without slip. The block starts with the
/// matching linear velocity profile, so the shear is homogeneous from the first step.
/// USF: with GIMP and a stress update from the post-integration velocities (USL, USAVG)
/// the rows of points next to a rigid no-slip plate carry a stress pattern the grid does
/// not see (first row ~0.6 τ, second ~1.2 τ), which creeps under relaxation; USF (and
/// linear shape functions with USAVG) keep the profile uniform to ~1 %.
fn shear_box(material: Material, v_top: f64) -> (Case, Particles) {
    let length = 6.0;
    let h = 0.125;
    let plate = |name: &str, v: f64| Body {
        motion: Motion::Prescribed(DVec2::new(v, 0.0)),
        ..Body::free(name, 0)
    };
    let mut s = setup(
        [-0.5, -0.5],
        h,
        [56, 16],
        vec![material],
        vec![
            Body::free("block", 0),
            plate("bottom", 0.0),
            plate("top", v_top),
        ],
        0.2,
    );
    s.contact = ContactTable::new(3, ContactLaw::NoSlip);
    s.scheme = UpdateScheme::Usf;
    let mut p = Particles::default();
    let rect = |lo: [f64; 2], hi: [f64; 2]| Geometry::Rectangle { lo, hi };
    fill(&mut p, &s, 0, &rect([0.0, 0.0], [length, 1.0]), |x| {
        DVec2::new(v_top * x.y, 0.0)
    });
    fill(&mut p, &s, 1, &rect([0.0, -0.25], [length, 0.0]), |_| {
        DVec2::ZERO
    });
    fill(&mut p, &s, 2, &rect([0.0, 1.0], [length, 1.25]), |_| {
        DVec2::new(v_top, 0.0)
    });
    (s, p)
}

/// Mean shear stress in the middle third of the block, away from its free ends and from
/// the rows of points next to the plates.
fn middle_shear(s: &State) -> f64 {
    let p = &s.particles;
    let inside = |i: usize| (p.pos[i].x - 3.0).abs() < 1.0 && (p.pos[i].y - 0.5).abs() < 0.375;
    mean(s, 0, inside, |i| p.stress[i].xy)
}

#[test]
fn j2_block_in_simple_shear() {
    // τ = G γ until τ = k = σ_y/√3; then, perfectly plastic, τ = k; with hardening H,
    // dτ/dγ = G H/(H + 3G).
    let yield_stress = 0.01;
    let rate = 0.01;
    for hardening in [0.0, 0.1] {
        let m = Material::J2Plastic {
            name: "j2".into(),
            density: 1.0,
            bulk: K,
            shear: G,
            yield_stress,
            hardening,
            expansion: 0.0,
        };
        let (setup, p) = shear_box(m, rate);
        let (mut s, mut w) = start(&setup, p);
        let mut curve = Vec::new();
        run_until(&setup, &mut s, &mut w, 5.0, |s, _| {
            curve.push((rate * s.time, middle_shear(s)))
        });
        let k = yield_stress / 3f64.sqrt();
        let elastic: Vec<_> = curve.iter().filter(|c| c.0 < 0.5 * k / G).collect();
        let (g, _) = fit(
            &elastic.iter().map(|c| c.0).collect::<Vec<_>>(),
            &elastic.iter().map(|c| c.1).collect::<Vec<_>>(),
        );
        assert!((g / G - 1.0).abs() < 0.01, "elastic slope {g}");
        let plastic: Vec<_> = curve.iter().filter(|c| c.0 > 3.0 * k / G).collect();
        let (slope, _) = fit(
            &plastic.iter().map(|c| c.0).collect::<Vec<_>>(),
            &plastic.iter().map(|c| c.1).collect::<Vec<_>>(),
        );
        eprintln!(
            "H = {hardening}: elastic slope {g}, plastic slope {slope}, final τ {}",
            curve.last().unwrap().1
        );
        if hardening == 0.0 {
            let tau = curve.last().unwrap().1;
            assert!((tau / k - 1.0).abs() < 0.01, "plateau {tau} vs k = {k}");
        } else {
            let expected = G * hardening / (hardening + 3.0 * G);
            assert!(
                (slope / expected - 1.0).abs() < 0.02,
                "slope {slope} vs {expected}"
            );
        }
        let d = diagnostics::measure(&setup, &s.particles, &w.layout().bodies);
        assert!(d.dissipated > 0.0 && d.bodies[0].plastic_max > 0.0);
    }
}

#[test]
fn maxwell_relaxation_under_held_shear() {
    // The top plate moves with a smooth bump v(t) = v̂ sin²(π t/t₁) for t < t₁ (≈ 3.5
    // shear-wave transits of the block, so the block follows without ringing), shearing
    // the block to γ₀ = v̂ t₁/2, then stops: the shear stress of a one-term Maxwell solid
    // (G∞ = 0) then decays as exp(−t/τ). The driver sets the plate's prescribed velocity
    // before every step, as a scenario's velocity table would.
    let tau = 10.0;
    let m = Material::Maxwell {
        name: "mx".into(),
        density: 1.0,
        bulk: K,
        shear: 0.0,
        prony: vec![PronyTerm {
            shear: G,
            time: tau,
        }],
        expansion: 0.0,
    };
    let (t1, peak) = (5.0, 0.004);
    let (mut setup, p) = shear_box(m, 0.0);
    let (mut s, mut w) = start(&setup, p);
    let (mut t, mut ln) = (Vec::new(), Vec::new());
    while s.time < t1 + 2.0 * tau {
        let u = (s.time + 0.5 * setup.dt) / t1;
        let v = if u < 1.0 {
            peak * (std::f64::consts::PI * u).sin().powi(2)
        } else {
            0.0
        };
        setup.bodies[2].motion = Motion::Prescribed(DVec2::new(v, 0.0));
        step(&setup, &mut s, &mut w, setup.dt).unwrap();
        if s.time > t1 + 1.0 {
            t.push(s.time);
            ln.push(middle_shear(&s).ln());
        }
    }
    let gamma = peak * t1 / 2.0;
    let (slope, _) = fit(&t, &ln);
    let fitted = -1.0 / slope;
    eprintln!("γ₀ = {gamma}: fitted relaxation time {fitted} (η/G = {tau})");
    assert!(
        (fitted / tau - 1.0).abs() < 0.02,
        "relaxation time {fitted} vs η/G = {tau}"
    );
    // What the plate's work stored in the branch is dissipated as it relaxes.
    let d = diagnostics::measure(&setup, &s.particles, &w.layout().bodies);
    assert!(d.dissipated > 0.0);
}

#[test]
fn free_thermal_expansion_of_a_disk() {
    // A free disk heated slowly (smooth ramp, ~50 wave transits): in plane strain its
    // in-plane strain is (1 + ν) α ΔT, in-plane stresses vanish and σ_zz = −E α ΔT.
    let (alpha, dtemp) = (1e-3, 10.0);
    let m = Material::LinearElastic {
        name: "hot".into(),
        density: 1.0,
        bulk: K,
        shear: G,
        expansion: alpha,
    };
    // Smoothstep 0 → ΔT over [0, 20], then held.
    let ramp = 20.0;
    let body = Body {
        temperature: Some(smoothstep(ramp, dtemp)),
        ..Body::free("disk", 0)
    };
    let setup = setup([0.0, 0.0], 0.05, [40, 40], vec![m], vec![body], 0.2);
    let centre = DVec2::splat(1.0);
    let disk = Geometry::Disk {
        centre: centre.to_array(),
        radius: 0.5,
    };
    let mut p = Particles::default();
    fill(&mut p, &setup, 0, &disk, |_| DVec2::ZERO);
    let (mut s, mut w) = start(&setup, p);
    run_until(&setup, &mut s, &mut w, ramp + 2.0, |_, _| {});
    let nu = (3.0 * K - 2.0 * G) / (2.0 * (3.0 * K + G));
    let e = 9.0 * K * G / (3.0 * K + G);
    let dth = alpha * dtemp;
    let pp = &s.particles;
    let strain = mean(&s, 0, |_| true, |i| 0.5 * pp.def[i].determinant().ln());
    assert!(
        (strain / ((1.0 + nu) * dth) - 1.0).abs() < 0.01,
        "strain {strain} vs (1 + ν) α ΔT = {}",
        (1.0 + nu) * dth
    );
    let max_in_plane = (0..pp.len())
        .map(|i| {
            let st = pp.stress[i];
            st.xx.abs().max(st.yy.abs()).max(st.xy.abs())
        })
        .fold(0.0, f64::max);
    assert!(max_in_plane / (K * dth) < 1e-3, "{max_in_plane}");
    let zz = mean(&s, 0, |_| true, |i| pp.stress[i].zz);
    eprintln!(
        "strain/((1+ν)αΔT) {}, max in-plane stress/(KαΔT) {}, σ_zz/(−EαΔT) {}",
        strain / ((1.0 + nu) * dth),
        max_in_plane / (K * dth),
        zz / (-e * dth)
    );
    assert!((zz / (-e * dth) - 1.0).abs() < 0.01, "σ_zz {zz}");
    // The thermal strain did the work now stored (and the little left as motion).
    let d = diagnostics::measure(&setup, &s.particles, &w.layout().bodies);
    assert!(
        d.balance().abs() < 1e-2 * d.thermal_work,
        "kinetic {} strain {} thermal work {}",
        d.kinetic,
        d.strain,
        d.thermal_work
    );
}

#[test]
fn kinetic_plus_stored_plus_dissipated_is_conserved() {
    // A free block set vibrating in a shear mode, strong enough to yield (J2) or to
    // spend its energy in the dashpots (Maxwell): what the motion loses is counted as
    // dissipated, so total + dissipated stays at its initial value to the scheme's own
    // accuracy (USF keeps an elastic vibration to ~1 %, tests/physics.rs).
    let materials = [
        Material::J2Plastic {
            name: "j2".into(),
            density: 1.0,
            bulk: K,
            shear: G,
            yield_stress: 0.01,
            hardening: 0.05,
            expansion: 0.0,
        },
        Material::Maxwell {
            name: "mx".into(),
            density: 1.0,
            bulk: K,
            shear: 0.2,
            prony: vec![
                PronyTerm {
                    shear: 0.2,
                    time: 0.5,
                },
                PronyTerm {
                    shear: 0.1,
                    time: 5.0,
                },
            ],
            expansion: 0.0,
        },
    ];
    for m in materials {
        let mut setup = setup(
            [0.0, 0.0],
            0.125,
            [32, 16],
            vec![m.clone()],
            vec![Body::free("block", 0)],
            0.2,
        );
        setup.scheme = UpdateScheme::Usf;
        let mut p = Particles::default();
        let block = Geometry::Rectangle {
            lo: [1.0, 0.5],
            hi: [3.0, 1.5],
        };
        fill(&mut p, &setup, 0, &block, |x| {
            DVec2::new(0.05 * (std::f64::consts::PI * (x.y - 1.0)).sin(), 0.0)
        });
        let (mut s, mut w) = start(&setup, p);
        let e0 = diagnostics::measure(&setup, &s.particles, &w.layout().bodies).balance();
        let mut worst = 0.0f64;
        run_until(&setup, &mut s, &mut w, 6.0, |s, w| {
            let d = diagnostics::measure(&setup, &s.particles, &w.layout().bodies);
            worst = worst.max((d.balance() / e0 - 1.0).abs());
        });
        let d = diagnostics::measure(&setup, &s.particles, &w.layout().bodies);
        eprintln!(
            "{}: dissipated {:.3} of E0, worst |balance/E0 − 1| {worst:.2e}",
            m.name(),
            d.dissipated / e0
        );
        assert!(d.dissipated > 0.2 * e0, "{m:?}: {}", d.dissipated / e0);
        assert!(worst < 0.02, "{m:?}: {worst}");
    }
}
