//! The energy ledger under the granular law closes: initial energy + outside work =
//! kinetic + potential + stored + what the ledger booked (dissipated, and the law's
//! changes without work), for a head-on Hertz impact with Tsuji damping, an oblique
//! impact that slides (Mindlin and `mindlin_rescale`), a sphere rolling on a flat
//! against `sds` resistance (and twisting against `marshall` in 3D), and a small bed
//! settling under the full law. The residual is the integrator's: each case runs at Δt
//! and Δt/2 and the residual must fall as the order the docs derive says.
//!
//! Built twice: as `grains-dem`'s test (2D, disks) and as `grains-dem3d`'s (3D).

#[cfg(feature = "dim3")]
use grains_dem3d as dem;

#[cfg(not(feature = "dim3"))]
use grains_dem as dem;

mod closure;

use closure::{at, converges, material, noise, placeholder, spin, Closure, RHO};
use dem::diagnostics::measure;
use dem::granular::{Damping, GranularParams, Normal, Rolling, Tangential};
use dem::math::{AngVector, Components, Vector, DIM};
use dem::{Domain, Hooks, PairTable, Particles, Setup, State};

/// Hertz with Tsuji damping at restitution `e`, tangential `t`, friction μ.
fn hertz(youngs: f64, e: f64, t: Tangential, mu: f64) -> GranularParams {
    GranularParams::lammps(
        Normal::HertzMaterial,
        youngs,
        Damping::Tsuji,
        e,
        0.3,
        t,
        None,
        1.0,
        mu,
    )
}

/// The full law: Hertz, Tsuji (e = 0.5), Mindlin (μ = 0.5), `sds` rolling (k_r = 200
/// N/m, γ_r, μ_r) and, in 3D, `marshall` twisting.
fn full(gamma_r: f64, mu_r: f64) -> GranularParams {
    let mut law = hertz(1e7, 0.5, Tangential::Mindlin, 0.5);
    law.rolling = Some(Rolling {
        kr: 200.0,
        gamma_r,
        mu_r,
    });
    law.twisting = DIM == 3;
    law
}

/// The set-up: two materials (0 the moving grains, 1 the held ones), one law, gravity
/// along −up, the box from `lo` to `hi` (periodic across when `periodic`).
fn setup(law: GranularParams, g: f64, lo: Vector, hi: Vector, periodic: bool) -> Setup {
    let model = placeholder();
    let mut p = [periodic; DIM];
    p[DIM - 1] = false;
    let domain = Domain {
        lo,
        hi,
        periodic: p,
    };
    let skin = 0.1 * (hi - lo).length() / 100.0;
    let mut s = Setup::new(
        domain,
        vec![material(), material()],
        model,
        vec![],
        at([0.0; 2], -g),
        skin,
    )
    .expect("a valid set-up");
    s.granular = Some(PairTable::from_fn(2, |_, _| law));
    s
}

/// Holds the particles of material 1 against gravity (their weight cancelled): they
/// are heavy enough to stay put, and the constant force's work, −m g·Δx, cancels their
/// potential energy's change, so the balance leaves their potential out.
struct Held {
    g: Vector,
}

impl Hooks for Held {
    fn post_force(&mut self, p: &mut Particles) {
        for i in 0..p.len() {
            if p.material[i] == 1 {
                let m = p.mass(i);
                p.force[i] -= m * self.g;
            }
        }
    }
}

/// Kinetic + potential of the free grains + the ledger's stored energy.
fn energy(setup: &Setup, s: &State) -> f64 {
    let p = &s.particles;
    let potential: f64 = (0..p.len())
        .filter(|&i| p.material[i] == 0)
        .map(|i| -p.mass(i) * setup.gravity.dot(p.pos[i]))
        .sum();
    measure(setup, s).kinetic() + potential + dem::ledger_sums::figures(s).unwrap().stored()
}

/// Runs `p` for `duration` at `dt` with the ledger on and measures its closure.
fn close(setup: &Setup, p: Particles, dt: f64, duration: f64) -> Closure {
    let mut s = State::new(setup, p);
    // The first half kick uses the set-up's forces, which no hook has seen.
    let mut held = Held { g: setup.gravity };
    held.post_force(&mut s.particles);
    dem::ledger_sums::start(setup, &mut s).expect("the ledger is kept");
    let start = energy(setup, &s);
    let steps = (duration / dt).round() as usize;
    for _ in 0..steps {
        dem::step_with(setup, &mut s, dt, &mut held);
    }
    let l = dem::ledger_sums::figures(&s).unwrap();
    // The ledger's springs are the diagnostics' (no walls here).
    let elastic = measure(setup, &s).elastic;
    assert!(
        (l.stored() - elastic).abs() <= 1e-9 * start,
        "stored {} vs elastic {elastic}",
        l.stored()
    );
    Closure {
        residual: (energy(setup, &s) + l.total() - start).abs() / start,
        start,
        ledger: l,
        state: s,
    }
}

/// Two spheres of radius `r` meeting at `closing` speed along x, the second moving
/// sideways (along the last axis) at `side`, the first spinning at `w`.
fn pair(r: f64, closing: f64, side: f64, w: AngVector) -> Particles {
    let mut p = Particles::default();
    let gap = 1e-3 * r;
    let half = 0.5 * closing;
    p.push(
        at([-(r + gap), 0.0], 0.0),
        r,
        RHO,
        0.4,
        0,
        at([half, 0.0], 0.0),
        w,
    );
    let mut v = at([-half, 0.0], 0.0);
    v[DIM - 1] = side;
    p.push(
        at([r + gap, 0.0], 0.0),
        r,
        RHO,
        0.4,
        0,
        v,
        AngVector::default(),
    );
    p
}

fn open_box(r: f64) -> (Vector, Vector) {
    let h = at([10.0 * r; 2], 10.0 * r);
    (-h, h)
}

#[test]
fn head_on_hertz_impact_with_tsuji_damping_closes() {
    let r = 0.01;
    let law = hertz(1e7, 0.7, Tangential::Mindlin, 0.3);
    let (lo, hi) = open_box(r);
    let s = setup(law, 0.0, lo, hi, false);
    let c = converges(
        "head-on",
        |dt| close(&s, pair(r, 1.0, 0.0, AngVector::default()), dt, 0.03),
        5e-6,
        3e-4,
    );
    let l = c.ledger;
    assert_eq!(measure(&s, &c.state).pair_contacts, 0, "parted");
    assert!(l.damping > 0.3 * c.start, "{l:?}");
    assert_eq!(
        (l.friction, l.damping_tangential, l.softening),
        (0.0, 0.0, 0.0)
    );
}

#[test]
fn oblique_impact_sliding_closes() {
    let r = 0.01;
    // Rescaling shows where the spring unloads before it slides: a gentler slip.
    for (t, side, bound) in [
        (Tangential::Mindlin, 1.5, 1e-4),
        (Tangential::MindlinRescale, 0.4, 1.5e-3),
    ] {
        let law = hertz(1e7, 0.7, t, 0.3);
        let (lo, hi) = open_box(r);
        let s = setup(law, 0.0, lo, hi, false);
        let c = converges(
            &format!("oblique {t:?}"),
            |dt| close(&s, pair(r, 1.0, side, spin(40.0, 0.0)), dt, 0.03),
            5e-6,
            bound,
        );
        let l = c.ledger;
        assert!(l.friction > 0.0 && l.damping_tangential > 0.0, "{l:?}");
        assert!(l.softening != 0.0, "{l:?}");
    }
}

#[test]
fn rolling_on_a_flat_against_sds_closes() {
    let r = 0.005;
    let big = 0.5;
    let law = full(0.02, 0.05);
    let lo = at([-1.0; 2], -1.2);
    let hi = at([1.0; 2], 0.2);
    let s = setup(law, 9.81, lo, hi, false);
    let make = || {
        let mut p = Particles::default();
        // The flat: a sphere 100 times larger, 1e6 times denser, held.
        p.push(
            at([0.0; 2], -big),
            big,
            1e6 * RHO,
            0.4,
            1,
            Vector::ZERO,
            AngVector::default(),
        );
        let v = 0.3;
        p.push(
            at([0.0; 2], r * (1.0 - 1e-4)),
            r,
            RHO,
            0.4,
            0,
            at([v, 0.0], 0.0),
            spin(v / r, 20.0),
        );
        p
    };
    let c = converges("rolling", |dt| close(&s, make(), dt, 0.1), 2e-5, 3e-5);
    let l = c.ledger;
    assert_eq!(measure(&s, &c.state).pair_contacts, 1, "still rolling");
    assert!(l.rolling_damping + l.rolling_friction > 0.0, "{l:?}");
    if DIM == 3 {
        assert!(l.twisting_damping + l.twisting_friction > 0.0, "{l:?}");
    }
}

#[test]
fn a_bed_settling_under_the_full_law_closes() {
    let law = full(0.01, 0.1);
    // Floor: held spheres of radius 1.5 mm touching in a square lattice (a grain of
    // radius ≥ 0.9 mm cannot pass their holes), periodic across.
    let (rf, cells) = (0.0015, 4usize);
    let width = 2.0 * rf * cells as f64;
    let lo = at([0.0; 2], -rf);
    let hi = at([width; 2], 0.05);
    let s = setup(law, 9.81, lo, hi, true);
    let make = || {
        let mut p = Particles::default();
        let across = if DIM == 3 { cells } else { 1 };
        for a in 0..cells {
            for b in 0..across {
                let h = [(a as f64 + 0.5) * 2.0 * rf, (b as f64 + 0.5) * 2.0 * rf];
                p.push(
                    at(h, 0.0),
                    rf,
                    1e6 * RHO,
                    0.4,
                    1,
                    Vector::ZERO,
                    AngVector::default(),
                );
            }
        }
        // Grains on a loose lattice above it, with random velocities and spins.
        let mut noise = noise();
        let (count, pitch) = (if DIM == 3 { 192 } else { 48 }, 2.2e-3);
        let per = (width / pitch) as usize;
        let layer = if DIM == 3 { per * per } else { per };
        for g in 0..count {
            let (a, b, c) = (g % per, (g / per) % per, g / layer);
            let h = [(a as f64 + 0.5) * pitch, (b as f64 + 0.5) * pitch];
            let up = rf + 2e-3 + c as f64 * pitch;
            let v = at([0.1 * noise(), 0.1 * noise()], 0.1 * noise());
            let w = <AngVector as Components>::from_slice(&[
                noise() * 50.0,
                noise() * 50.0,
                noise() * 50.0,
            ]);
            p.push(at(h, up), 0.001 * (0.95 + 0.1 * noise()), RHO, 0.4, 0, v, w);
        }
        p
    };
    let c = converges("settling bed", |dt| close(&s, make(), dt, 0.08), 5e-6, 4e-3);
    let l = c.ledger;
    assert!(
        l.friction > 0.0 && l.rolling_damping + l.rolling_friction > 0.0,
        "{l:?}"
    );
}
