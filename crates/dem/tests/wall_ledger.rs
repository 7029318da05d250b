//! The energy ledger closes with wall contacts under the granular law: initial energy +
//! the moving walls' work = kinetic + potential + stored (walls' springs included) +
//! what the ledger booked, for a sphere bouncing on a floor (Hertz, Tsuji), a sphere
//! sliding and rolling along a floor (Mindlin, `sds`, and `marshall` in 3D), a small
//! bed settling in a box of walls, the same bed on a floor that slides under it (a
//! conveyor: the wall works through friction) and grains in a turning drum. As in
//! `granular_ledger.rs`, each case runs at Δt and Δt/2 and the residual must be first
//! order in Δt.
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
use dem::{Domain, PairTable, Particles, Setup, State};
use dem::{Wall, WallShape};

/// Hertz (E = 1e7 Pa) with Tsuji damping at restitution `e`, Mindlin, friction `mu`;
/// `sds` rolling (and `marshall` twisting in 3D) when `rolling`.
fn law(e: f64, mu: f64, rolling: bool) -> GranularParams {
    let mut law = GranularParams::lammps(
        Normal::HertzMaterial,
        1e7,
        Damping::Tsuji,
        e,
        0.3,
        Tangential::Mindlin,
        None,
        1.0,
        mu,
    );
    if rolling {
        law.rolling = Some(Rolling {
            kr: 200.0,
            gamma_r: 0.01,
            mu_r: 0.1,
        });
        law.twisting = DIM == 3;
    }
    law
}

/// A flat wall through `point` facing `normal`: a plane.
#[cfg(feature = "dim3")]
fn flat(name: &str, point: Vector, normal: Vector) -> Wall {
    let shape = WallShape::Plane {
        point: point.to_array(),
        normal: normal.to_array(),
    };
    Wall::fixed(name, shape, None)
}

/// A flat wall through `point` facing `normal`: a segment 20 m long.
#[cfg(not(feature = "dim3"))]
fn flat(name: &str, point: Vector, normal: Vector) -> Wall {
    let along = Vector::new(-normal.y, normal.x) * 10.0;
    let shape = WallShape::Segment {
        a: (point - along).to_array(),
        b: (point + along).to_array(),
    };
    Wall::fixed(name, shape, None)
}

/// A drum of radius `r` about the origin (in 3D along the second axis), inside.
#[cfg(feature = "dim3")]
fn drum(r: f64) -> WallShape {
    WallShape::Cylinder {
        point: [0.0; 3],
        axis: [0.0, 1.0, 0.0],
        radius: r,
        inside: true,
    }
}

/// A drum of radius `r` about the origin, inside.
#[cfg(not(feature = "dim3"))]
fn drum(r: f64) -> WallShape {
    WallShape::Circle {
        centre: [0.0; 2],
        radius: r,
        inside: true,
    }
}

/// The set-up: one material, `law`, gravity g along −up, `walls`, the box from `lo` to
/// `hi` (periodic along the axes `periodic` names).
fn setup(
    law: GranularParams,
    g: f64,
    (lo, hi): (Vector, Vector),
    periodic: [bool; DIM],
    walls: Vec<Wall>,
) -> Setup {
    let domain = Domain { lo, hi, periodic };
    let skin = 1e-3 * (hi - lo).length();
    let g = at([0.0; 2], -g);
    let mut s = Setup::new(domain, vec![material()], placeholder(), walls, g, skin)
        .expect("a valid set-up");
    s.granular = Some(PairTable::from_fn(1, |_, _| law));
    s
}

/// Kinetic + potential (zero at the bottom of the box) + the ledger's stored energy.
fn energy(setup: &Setup, s: &State) -> f64 {
    let p = &s.particles;
    let potential: f64 = (0..p.len())
        .map(|i| -p.mass(i) * setup.gravity.dot(p.pos[i] - setup.domain.lo))
        .sum();
    measure(setup, s).kinetic() + potential + dem::ledger_sums::figures(s).unwrap().stored()
}

/// Runs `p` for `duration` at `dt` with the ledger on, the walls moving, and measures
/// its closure against the energy at the start and the walls' work.
fn close(setup: &Setup, p: Particles, dt: f64, duration: f64) -> Closure {
    let mut setup = setup.clone();
    let mut s = State::new(&setup, p);
    dem::ledger_sums::start(&setup, &mut s).expect("the ledger is kept");
    let start = energy(&setup, &s);
    let steps = (duration / dt).round() as usize;
    for _ in 0..steps {
        dem::walls::advance_walls(&mut setup, &mut s, dt);
        dem::step(&setup, &mut s, dt);
    }
    let l = dem::ledger_sums::figures(&s).unwrap();
    // The ledger's springs, the walls' included, are the diagnostics'.
    let elastic = measure(&setup, &s).elastic;
    assert!(
        (l.stored() - elastic).abs() <= 1e-9 * start,
        "stored {} vs elastic {elastic}",
        l.stored()
    );
    let reference = start + l.wall_work.abs();
    Closure {
        residual: (energy(&setup, &s) + l.total() - l.wall_work - start).abs() / reference,
        start,
        ledger: l,
        state: s,
    }
}

/// A box about the origin, `half` wide across and from the floor (0) to `top` upright.
fn room(half: f64, top: f64) -> (Vector, Vector) {
    (at([-half; 2], 0.0), at([half; 2], top))
}

fn one(x: Vector, r: f64, v: Vector, w: AngVector) -> Particles {
    let mut p = Particles::default();
    p.push(x, r, RHO, 0.4, 0, v, w);
    p
}

#[test]
fn a_sphere_bouncing_on_a_floor_closes() {
    let r = 0.01;
    let floor = flat("floor", Vector::ZERO, at([0.0; 2], 1.0));
    let s = setup(
        law(0.7, 0.3, false),
        9.81,
        room(0.1, 0.1),
        [false; DIM],
        vec![floor],
    );
    let c = converges(
        "bounce",
        |dt| {
            let x = at([0.0; 2], r * (1.0 + 1e-3));
            close(&s, one(x, r, at([0.0; 2], -1.0), spin(0.0, 0.0)), dt, 0.02)
        },
        5e-6,
        3e-4,
    );
    let l = c.ledger;
    assert_eq!(measure(&s, &c.state).wall_contacts, 0, "bounced off");
    assert!(l.damping > 0.3 * c.start, "{l:?}");
    assert_eq!((l.friction, l.wall_work), (0.0, 0.0), "{l:?}");
}

#[test]
fn a_sphere_sliding_and_rolling_on_a_floor_closes() {
    let r = 0.005;
    let floor = flat("floor", Vector::ZERO, at([0.0; 2], 1.0));
    let s = setup(
        law(0.5, 0.3, true),
        9.81,
        room(0.5, 0.1),
        [false; DIM],
        vec![floor],
    );
    // Thrown along the floor with backspin and a twist: it slides, then rolls.
    let make = || {
        let x = at([0.0; 2], r * (1.0 - 1e-4));
        one(x, r, at([0.3, 0.0], 0.0), spin(-20.0, 20.0))
    };
    let c = converges(
        "slide and roll",
        |dt| close(&s, make(), dt, 0.1),
        2e-5,
        3e-4,
    );
    let l = c.ledger;
    assert_eq!(measure(&s, &c.state).wall_contacts, 1, "still on the floor");
    assert!(l.friction > 0.0, "{l:?}");
    assert!(l.rolling_damping + l.rolling_friction > 0.0, "{l:?}");
    if DIM == 3 {
        assert!(l.twisting_damping + l.twisting_friction > 0.0, "{l:?}");
    }
}

/// Grains on a loose lattice over a floor `width` wide (and deep in 3D), with random
/// velocities and spins.
fn grains(width: f64, count: usize) -> Particles {
    let mut p = Particles::default();
    let mut noise = noise();
    let pitch = 2.2e-3;
    let per = (width / pitch) as usize;
    let layer = if DIM == 3 { per * per } else { per };
    for g in 0..count {
        let (a, b, c) = (g % per, (g / per) % per, g / layer);
        let h = [
            (a as f64 + 0.5) * pitch - 0.5 * width,
            (b as f64 + 0.5) * pitch - 0.5 * width,
        ];
        let v = at([0.1 * noise(), 0.1 * noise()], 0.1 * noise());
        let w = <AngVector as Components>::from_slice(&[
            noise() * 50.0,
            noise() * 50.0,
            noise() * 50.0,
        ]);
        let up = 2e-3 + c as f64 * pitch;
        p.push(at(h, up), 0.001 * (0.95 + 0.1 * noise()), RHO, 0.4, 0, v, w);
    }
    p
}

/// A floor and side walls around a square `width` across (in 3D, four sides).
fn box_walls(width: f64) -> Vec<Wall> {
    let half = 0.5 * width;
    let mut walls = vec![flat("floor", Vector::ZERO, at([0.0; 2], 1.0))];
    for a in 0..DIM - 1 {
        for side in [-1.0, 1.0] {
            let mut n = Vector::ZERO;
            n[a] = side;
            walls.push(flat(&format!("side{a}{side}"), half * n, n));
        }
    }
    walls
}

const BED: (f64, usize) = (0.0088, if DIM == 3 { 96 } else { 24 });

#[test]
fn a_bed_settling_in_a_box_of_walls_closes() {
    let (width, count) = BED;
    let s = setup(
        law(0.5, 0.5, true),
        9.81,
        room(width, 0.05),
        [false; DIM],
        box_walls(width),
    );
    let c = converges(
        "bed in a box",
        |dt| close(&s, grains(width, count), dt, 0.08),
        5e-6,
        4e-3,
    );
    let l = c.ledger;
    assert!(measure(&s, &c.state).wall_contacts > 0, "{l:?}");
    assert!(l.walls.total() > 0.0 && l.friction > 0.0, "{l:?}");
}

#[test]
fn a_floor_sliding_under_a_bed_works_on_it() {
    let (width, count) = BED;
    // A conveyor: the floor moves along itself (its shape does not change), dragging
    // the grains by friction against the box's fixed sides.
    let mut walls = box_walls(width);
    walls[0].motion.velocity = at([0.05, 0.0], 0.0);
    let s = setup(
        law(0.5, 0.5, true),
        9.81,
        room(width, 0.05),
        [false; DIM],
        walls,
    );
    let c = converges(
        "conveyor",
        |dt| close(&s, grains(width, count), dt, 0.08),
        5e-6,
        4e-3,
    );
    assert!(c.ledger.wall_work > 0.0, "{:?}", c.ledger);
}

#[test]
fn a_turning_drum_works_on_its_grains() {
    let (rd, count) = (0.008, if DIM == 3 { 48 } else { 16 });
    // The drum about the second axis in 3D (periodic along it), about the origin in 2D.
    let mut drum = Wall::fixed("drum", drum(rd), None);
    drum.motion.omega = spin(10.0, 0.0);
    let mut periodic = [false; DIM];
    let lo = at([-rd, -0.0044], -rd) * 1.1;
    let hi = at([rd, 0.0044], rd) * 1.1;
    if DIM == 3 {
        periodic[1] = true;
    }
    let s = setup(law(0.5, 0.5, true), 9.81, (lo, hi), periodic, vec![drum]);
    let make = || {
        let mut p = grains(0.0088, count);
        for x in p.pos.iter_mut() {
            x[DIM - 1] -= 0.006;
        }
        p
    };
    let c = converges("drum", |dt| close(&s, make(), dt, 0.08), 5e-6, 4e-3);
    assert!(c.ledger.wall_work > 0.0, "{:?}", c.ledger);
}
