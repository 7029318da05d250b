//! Single-point tests of the models: objectivity, the return map, the Prony closed form,
//! thermal strain and the energy balance.

use super::*;
use crate::material::PronyTerm;
use std::f64::consts::FRAC_PI_2;

const K: f64 = 1.0;
const G: f64 = 0.5;

fn lin(expansion: f64) -> Material {
    Material::LinearElastic {
        name: "lin".into(),
        density: 1.0,
        bulk: K,
        shear: G,
        expansion,
    }
}

fn nh() -> Material {
    Material::NeoHookean {
        name: "nh".into(),
        density: 1.0,
        bulk: K,
        shear: G,
    }
}

fn j2(hardening: f64, expansion: f64) -> Material {
    Material::J2Plastic {
        name: "j2".into(),
        density: 1.0,
        bulk: K,
        shear: G,
        yield_stress: 0.01,
        hardening,
        expansion,
    }
}

fn maxwell(g_inf: f64, terms: &[(f64, f64)]) -> Material {
    Material::Maxwell {
        name: "mx".into(),
        density: 1.0,
        bulk: K,
        shear: g_inf,
        prony: terms
            .iter()
            .map(|&(shear, time)| PronyTerm { shear, time })
            .collect(),
        expansion: 1e-3,
    }
}

/// Pure shear at engineering shear rate `rate` (no spin): D_xy = rate/2.
fn shear(rate: f64) -> DMat2 {
    DMat2::from_cols_array(&[0.0, 0.5 * rate, 0.5 * rate, 0.0])
}

/// Rigid spin at `w` rad/s: v = w (−y, x).
fn spin_l(w: f64) -> DMat2 {
    DMat2::from_cols_array(&[0.0, w, -w, 0.0])
}

fn branch_norms(p: &PointState) -> Vec<f64> {
    p.branches.iter().map(|b| branch_norm2(*b)).collect()
}

#[test]
fn rigid_rotation_is_objective_for_every_model() {
    // Load into the interesting regime (past yield for J2, with live branches for
    // Maxwell, with a temperature change for the thermal ones), then either hold for a
    // time T or spin a quarter turn over the same T while the temperature keeps
    // changing: the invariants, the internal state and the energy accounts must agree.
    let stretch = DMat2::from_cols_array(&[0.02, 0.004, 0.004, -0.01]);
    for m in [
        lin(0.0),
        lin(1e-3),
        nh(),
        j2(0.0, 0.0),
        j2(0.2, 1e-3),
        maxwell(0.1, &[(0.4, 2.0), (0.3, 0.3)]),
    ] {
        let mut held = PointState::new(&m);
        held.drive(&m, stretch, 0.01, 0.1, 100);
        if let Material::J2Plastic { .. } = m {
            assert!(held.plastic > 0.0, "the J2 point must have yielded");
        }
        let mut spun = held.clone();
        let n = 4000;
        let dt = 1.0 / n as f64;
        held.drive(&m, DMat2::ZERO, dt, 0.05 * dt, n);
        spun.drive(&m, spin_l(FRAC_PI_2), dt, 0.05 * dt, n);
        let (a, b) = (held.stress, spun.stress);
        let scale = a.principal_difference().max(a.pressure().abs());
        let near = |x: f64, y: f64| (x - y).abs() <= 1e-9 * scale.max(1e-300);
        assert!(near(a.pressure(), b.pressure()), "{m:?}: {a:?} vs {b:?}");
        assert!(
            near(a.principal_difference(), b.principal_difference()),
            "{m:?}"
        );
        assert!(near(a.zz, b.zz), "{m:?}");
        // A quarter turn swaps the in-plane axes (the Hughes–Winget angle is exact up to
        // O(Δt²) per step).
        assert!((b.yy - a.xx).abs() < 1e-5 * scale, "{m:?}: {a:?} vs {b:?}");
        assert!((b.xy + a.xy).abs() < 1e-5 * scale, "{m:?}: {a:?} vs {b:?}");
        assert!(
            (held.plastic - spun.plastic).abs() <= 1e-12 * held.plastic,
            "{m:?}"
        );
        assert!((held.dissipated - spun.dissipated).abs() <= 1e-9 * held.dissipated.abs());
        assert!((held.thermal_work - spun.thermal_work).abs() <= 1e-9 * scale * scale);
        for (x, y) in branch_norms(&held).iter().zip(branch_norms(&spun)) {
            assert!((x - y).abs() <= 1e-9 * x, "{m:?}: {x} vs {y}");
        }
        let (ja, jb) = (held.def.determinant(), spun.def.determinant());
        assert!((ja - jb).abs() < 1e-12, "{m:?}: volume drifted");
    }
}

#[test]
fn j2_return_lands_on_the_yield_surface() {
    for h in [0.0, 0.05, 1.0] {
        let m = j2(h, 0.0);
        let mut p = PointState::new(&m);
        let prep = m.prepare(0.01, Thermal::default());
        let l = DMat2::from_cols_array(&[0.3, 0.2, 0.1, -0.1]);
        let mut yielded = 0;
        for _ in 0..3000 {
            let before = p.plastic;
            p.update(&prep, l);
            let surface = 0.01 + h * p.plastic;
            let q = p.stress.von_mises();
            if p.plastic > before {
                yielded += 1;
                assert!(
                    (q - surface).abs() < 1e-12 * surface,
                    "h = {h}: {q} vs {surface}"
                );
            } else {
                assert!(
                    q <= surface * (1.0 + 1e-12),
                    "h = {h}: elastic beyond yield"
                );
            }
        }
        assert!(yielded > 2000, "{yielded}");
    }
}

#[test]
fn j2_shear_plateau_and_hardening_slope() {
    // Pure shear: τ = G γ up to k = σ_y/√3, then dτ/dγ = G H/(H + 3G).
    let dt = 1e-3;
    let rate = 1.0;
    for h in [0.0, 0.1] {
        let m = j2(h, 0.0);
        let mut p = PointState::new(&m);
        let prep = m.prepare(dt, Thermal::default());
        let mut curve = Vec::new();
        for k in 1..=100 {
            p.update(&prep, shear(rate));
            curve.push((k as f64 * rate * dt, p.stress.xy));
        }
        let k_yield = 0.01 / 3f64.sqrt();
        let (g1, t1) = curve[59];
        let (g2, t2) = curve[99];
        if h == 0.0 {
            assert!((t2 - k_yield).abs() < 1e-12 * k_yield, "{t2} vs {k_yield}");
        } else {
            let slope = (t2 - t1) / (g2 - g1);
            let expected = G * h / (h + 3.0 * G);
            assert!(
                (slope - expected).abs() < 1e-9 * expected,
                "{slope} vs {expected}"
            );
            // The plastic strain follows from the stress: q = σ_y + H ε̄ᵖ.
            let ep = (3f64.sqrt() * t2 - 0.01) / h;
            assert!((p.plastic - ep).abs() < 1e-9 * ep);
        }
        // Elastic part: τ = G γ before yield.
        let (g0, t0) = curve[5];
        assert!((t0 - G * g0).abs() < 1e-12, "{t0}");
    }
}

#[test]
fn prony_one_term_matches_the_closed_form() {
    // Constant shear rate from rest: τ(t) = G∞ γ̇ t + G₁τ₁ γ̇ (1 − e^(−t/τ₁)); then held:
    // the branch relaxes as e^(−t/τ₁).
    let (g_inf, g1, tau) = (0.05, 0.4, 0.2);
    let m = maxwell(g_inf, &[(g1, tau)]);
    let mut p = PointState::new(&m);
    let (dt, rate) = (1e-3, 0.02);
    let prep = m.prepare(dt, Thermal::default());
    for k in 1..=500 {
        p.update(&prep, shear(rate));
        let t = k as f64 * dt;
        let exact = g_inf * rate * t + g1 * tau * rate * (1.0 - (-t / tau).exp());
        assert!((p.stress.xy - exact).abs() < 1e-12 * exact, "t = {t}");
    }
    let t1 = 500.0 * dt;
    let gamma = rate * t1;
    let branch0 = g1 * tau * rate * (1.0 - (-t1 / tau).exp());
    for k in 1..=1000 {
        p.update(&prep, DMat2::ZERO);
        let t = k as f64 * dt;
        let exact = g_inf * gamma + branch0 * (-t / tau).exp();
        assert!(
            (p.stress.xy - exact).abs() < 1e-12 * branch0,
            "hold t = {t}"
        );
    }
    // Pressure is untouched by the deviatoric model.
    assert!(p.stress.pressure().abs() < 1e-15);
}

#[test]
fn free_thermal_expansion_in_plane_strain() {
    // In plane strain a free body heated by ΔT strains (1 + ν) α ΔT in plane (α ΔT in each
    // of three directions, plus the Poisson share of the confined z direction), carries
    // no in-plane stress, and σ_zz = −E α ΔT.
    let alpha = 1e-3;
    let m = lin(alpha);
    let nu = (3.0 * K - 2.0 * G) / (2.0 * (3.0 * K + G));
    let e = 9.0 * K * G / (3.0 * K + G);
    let (dt, dtemp, n) = (0.01, 0.2, 100);
    let rate = (1.0 + nu) * alpha * dtemp / dt;
    let mut p = PointState::new(&m);
    p.drive(
        &m,
        DMat2::from_diagonal(glam::DVec2::splat(rate)),
        dt,
        dtemp,
        n,
    );
    let dth = alpha * dtemp * n as f64;
    let scale = K * dth;
    let s = p.stress;
    for x in [s.xx, s.yy, s.xy] {
        assert!(x.abs() < 1e-12 * scale, "{s:?}");
    }
    assert!(
        (s.zz + e * dth).abs() < 1e-12 * scale,
        "{} vs {}",
        s.zz,
        -e * dth
    );
    // The rate form integrates the logarithmic strain.
    let strain = p.def.x_axis.x.ln();
    assert!((strain - (1.0 + nu) * dth).abs() < 1e-6 * dth, "{strain}");
    // Confined heating: σ = −3Kα ΔT in every direction, and the thermal work is the
    // stored energy.
    let mut c = PointState::new(&m);
    c.drive(&m, DMat2::ZERO, dt, dtemp, n);
    for x in [c.stress.xx, c.stress.yy, c.stress.zz] {
        assert!((x + 3.0 * K * dth).abs() < 1e-12, "{:?}", c.stress);
    }
    let stored = c.stored(&m);
    assert!((stored - 4.5 * K * dth * dth).abs() < 1e-9 * stored);
    assert!((c.thermal_work - stored).abs() < 1e-9 * stored);
}

#[test]
fn work_is_stored_or_dissipated() {
    // Load, unload and reload; the stress power (midpoint rule) must equal the change
    // of stored energy plus what the model says it dissipated. Isochoric paths: under a
    // volume change the rate form's pressure (K ln J) and the stored-energy formula
    // (p²/2K per current volume) part ways at second order, as for the elastic model.
    let materials = [
        j2(0.0, 0.0),
        j2(0.3, 0.0),
        maxwell(0.1, &[(0.4, 0.05), (0.2, 0.5), (1.0, 5.0)]),
    ];
    for m in materials {
        let mut p = PointState::new(&m);
        let dt = 1e-3;
        let prep = m.prepare(dt, Thermal::default());
        let mut work = 0.0;
        let ls = [
            DMat2::from_cols_array(&[0.04, 0.03, 0.01, -0.04]),
            DMat2::from_cols_array(&[-0.04, -0.03, -0.01, 0.04]),
            DMat2::from_cols_array(&[0.03, 0.05, 0.02, -0.03]),
        ];
        for l in ls {
            for _ in 0..200 {
                let (s0, v0) = (p.stress, p.def.determinant());
                p.update(&prep, l);
                let (s1, v1) = (p.stress, p.def.determinant());
                let dxy = 0.5 * (l.y_axis.x + l.x_axis.y);
                let power = |s: Stress| s.xx * l.x_axis.x + s.yy * l.y_axis.y + 2.0 * s.xy * dxy;
                work += 0.5 * (power(s0) * v0 + power(s1) * v1) * dt;
            }
        }
        let stored = p.stored(&m);
        assert!(p.dissipated > 0.0, "{m:?}");
        let gap = work - stored - p.dissipated;
        assert!(
            gap.abs() < 1e-4 * work,
            "{m:?}: work {work} stored {stored} dissipated {}",
            p.dissipated
        );
    }
}

#[test]
fn prony_dissipation_constants_are_continuous_at_the_series_switch() {
    let term = PronyTerm {
        shear: 2.0,
        time: 1.0,
    };
    let (below, above) = (
        TermStep::new(term, 1e-3 * (1.0 - 1e-9)),
        TermStep::new(term, 1e-3),
    );
    assert!((below.diss_dd / above.diss_dd - 1.0).abs() < 1e-8);
    // Small steps: x³/3 k τ.
    let t = TermStep::new(term, 1e-6);
    assert!((t.diss_dd / (4.0 * 1e-18 / 3.0) - 1.0).abs() < 1e-5);
}
