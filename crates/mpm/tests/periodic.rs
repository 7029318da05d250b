//! A grid periodic along y: bodies crossing the seam, a body spanning the period, contact
//! through the seam. Each case is compared with the same motion on a grid without the
//! seam, or with itself shifted along y, so the seam must be invisible.

mod common;

use common::{fill, setup, start, Case};
use glam::DVec2;
use grains_mpm::diagnostics::measure;
use grains_mpm::*;

fn elastic() -> Material {
    Material::LinearElastic {
        name: "e".into(),
        density: 1.0,
        bulk: 1.0,
        shear: 0.5,
        expansion: 0.0,
    }
}

/// 16 cells of 0.125 across; `rows` cells along y; periodic or not.
fn case(rows: usize, periodic: bool, n: usize, shape: ShapeFunction, scheme: UpdateScheme) -> Case {
    let bodies = (0..n).map(|k| Body::free(format!("b{k}"), 0)).collect();
    let mut c = setup([0.0, 0.0], 0.125, [16, rows], vec![elastic()], bodies, 0.2);
    c.grid.periodic_y = periodic;
    c.shape = shape;
    c.scheme = scheme;
    c.separation = Some(contact::touching_separation(shape, 2) * 1.05 * 0.125);
    c.setup.validate().unwrap();
    c
}

/// A velocity field with a uniform drift and a little shear and stretch, so the disk
/// deforms while it moves.
fn drift(centre: DVec2, v: DVec2) -> impl Fn(DVec2) -> DVec2 {
    move |x: DVec2| {
        let d = x - centre;
        v + DVec2::new(0.05 * d.y, 0.03 * d.y + 0.02 * d.x)
    }
}

/// The points in id order: (position, velocity, σ_xx, σ_xy).
fn by_id(s: &State) -> Vec<(DVec2, DVec2, f64, f64)> {
    let p = &s.particles;
    let mut out = vec![(DVec2::ZERO, DVec2::ZERO, 0.0, 0.0); p.len()];
    for i in 0..p.len() {
        out[p.id[i] as usize] = (p.pos[i], p.vel[i], p.stress[i].xx, p.stress[i].xy);
    }
    out
}

#[test]
fn a_disk_crossing_the_seam_moves_as_without_it() {
    for shape in [
        ShapeFunction::Linear,
        ShapeFunction::Gimp,
        ShapeFunction::Bspline2,
    ] {
        for scheme in [
            UpdateScheme::Usf,
            UpdateScheme::Usl,
            UpdateScheme::Usavg,
            UpdateScheme::Musl,
        ] {
            // Periodic: 16 × 16 cells (period 2); the disk starts below the top and crosses
            // it. Reference: 16 × 32 cells without the seam.
            let (per, tall) = (
                case(16, true, 1, shape, scheme),
                case(32, false, 1, shape, scheme),
            );
            let centre = DVec2::new(1.0, 1.55);
            let disk = Geometry::Disk {
                centre: centre.to_array(),
                radius: 0.4,
            };
            let v = DVec2::new(0.05, 0.25);
            let (mut pp, mut pt) = (Particles::default(), Particles::default());
            fill(&mut pp, &per, 0, &disk, drift(centre, v));
            fill(&mut pt, &tall, 0, &disk, drift(centre, v));
            let (mut a, mut wa) = start(&per, pp);
            let (mut b, mut wb) = start(&tall, pt);
            let mass0: f64 = a.particles.mass.iter().sum();
            let p0 = measure(&per, &a.particles, &wa.layout().bodies).momentum;
            let dt = per.dt;
            let mut crossed = false;
            for _ in 0..(3.0 / dt) as usize {
                step(&per, &mut a, &mut wa, dt).unwrap();
                step(&tall, &mut b, &mut wb, dt).unwrap();
                let d = measure(&per, &a.particles, &wa.layout().bodies);
                let mass: f64 = a.particles.mass.iter().sum();
                assert_eq!(mass, mass0);
                assert!(
                    (d.momentum - p0).length() < 1e-14,
                    "{shape:?} {scheme:?}: {:?} vs {p0:?}",
                    d.momentum
                );
                assert!(a.particles.pos.iter().all(|x| x.y >= 0.0 && x.y < 2.0));
                crossed |= a.particles.pos.iter().any(|x| x.y < 0.5);
            }
            assert!(crossed, "the disk never crossed the seam");
            for ((xa, va, sa, ta), (xb, vb, sb, tb)) in by_id(&a).into_iter().zip(by_id(&b)) {
                let mut dx = xa - xb;
                dx.y -= 2.0 * (dx.y / 2.0).round();
                assert!(dx.length() < 1e-12, "{shape:?} {scheme:?}: {xa} vs {xb}");
                assert!((va - vb).length() < 1e-12, "{shape:?} {scheme:?}");
                assert!((sa - sb).abs() < 1e-12 && (ta - tb).abs() < 1e-12);
            }
            // The diagnostics see the disk whole: its centre moved with the drift.
            let d = measure(&per, &a.particles, &wa.layout().bodies);
            let e = measure(&tall, &b.particles, &wb.layout().bodies);
            let mut dc = d.bodies[0].centre - e.bodies[0].centre;
            dc.y -= 2.0 * (dc.y / 2.0).round();
            assert!(
                dc.length() < 1e-12,
                "{:?} vs {:?}",
                d.bodies[0],
                e.bodies[0]
            );
            assert!((d.bodies[0].omega - e.bodies[0].omega).abs() < 1e-10);
            assert!((d.strain - e.strain).abs() < 1e-14 && (d.kinetic - e.kinetic).abs() < 1e-14);
        }
    }
}

#[test]
fn a_strip_spanning_the_period_is_the_same_seen_from_any_row() {
    // A strip as tall as the period (a binder connected through the seam) carrying a
    // standing shear wave. Shifting the whole set-up by 5 cells along y must shift the
    // result and change nothing else: the seam is not a surface.
    let run = |shift: f64| {
        let c = case(16, true, 1, ShapeFunction::Gimp, UpdateScheme::Usavg);
        let strip = Geometry::Rectangle {
            lo: [0.5, 0.0],
            hi: [1.5, 2.0],
        };
        let mut p = Particles::default();
        let wave = |x: DVec2| {
            let phase = std::f64::consts::TAU * x.y / 2.0;
            DVec2::new(0.05 * phase.sin(), 0.0)
        };
        fill(&mut p, &c, 0, &strip, wave);
        for x in &mut p.pos {
            *x = c.grid.wrap(*x + DVec2::new(0.0, shift));
        }
        p.pos0.clone_from(&p.pos);
        let (mut s, mut w) = start(&c, p);
        for _ in 0..400 {
            step(&c, &mut s, &mut w, c.dt).unwrap();
        }
        let d = measure(&c, &s.particles, &w.layout().bodies);
        (by_id(&s), d)
    };
    let (a, da) = run(0.0);
    let (b, db) = run(5.0 * 0.125);
    assert!(
        da.strain > 1e-5,
        "the wave must strain the strip: {}",
        da.strain
    );
    assert!((da.strain - db.strain).abs() < 1e-12 * da.strain);
    assert!((da.kinetic - db.kinetic).abs() < 1e-12 * da.strain);
    for ((xa, va, sa, ta), (xb, vb, sb, tb)) in a.into_iter().zip(b) {
        let mut dx = xb - xa - DVec2::new(0.0, 0.625);
        dx.y -= 2.0 * (dx.y / 2.0).round();
        assert!(dx.length() < 1e-12, "{xa} vs {xb}");
        assert!((va - vb).length() < 1e-12);
        assert!((sa - sb).abs() < 1e-12 && (ta - tb).abs() < 1e-12);
    }
}

#[test]
fn disks_collide_through_the_seam() {
    // One disk just below the top moving up, one just above the bottom moving down: they
    // meet at the seam (and are 1.1 apart the other way round the period of 3). The same
    // pair in a taller grid without the seam is the reference.
    let (per, tall) = (
        case(24, true, 2, ShapeFunction::Gimp, UpdateScheme::Usavg),
        case(48, false, 2, ShapeFunction::Gimp, UpdateScheme::Usavg),
    );
    let fill_pair = |c: &Case| {
        let mut p = Particles::default();
        for (b, y, vy) in [(0u16, 2.45, 0.2), (1, 3.55, -0.2)] {
            let disk = Geometry::Disk {
                centre: [1.0, y],
                radius: 0.4,
            };
            fill(&mut p, c, b, &disk, |_| DVec2::new(0.0, vy));
        }
        for x in &mut p.pos {
            *x = c.grid.wrap(*x);
        }
        p.pos0.clone_from(&p.pos);
        p
    };
    let (mut a, mut wa) = start(&per, fill_pair(&per));
    let (mut b, mut wb) = start(&tall, fill_pair(&tall));
    let mut touched = false;
    for _ in 0..(4.0 / per.dt) as usize {
        step(&per, &mut a, &mut wa, per.dt).unwrap();
        step(&tall, &mut b, &mut wb, per.dt).unwrap();
        touched |= a.touch[0].body_nodes > 0;
        let d = measure(&per, &a.particles, &wa.layout().bodies);
        assert!(d.momentum.length() < 1e-13, "{:?}", d.momentum);
    }
    assert!(touched, "the disks never met");
    let d = measure(&per, &a.particles, &wa.layout().bodies);
    assert!(
        d.bodies[0].velocity.y < -0.05 && d.bodies[1].velocity.y > 0.05,
        "they rebound"
    );
    for ((xa, va, sa, _), (xb, vb, sb, _)) in by_id(&a).into_iter().zip(by_id(&b)) {
        let mut dx = xa - xb;
        dx.y -= 3.0 * (dx.y / 3.0).round();
        assert!(dx.length() < 1e-11, "{xa} vs {xb}");
        assert!((va - vb).length() < 1e-11);
        assert!((sa - sb).abs() < 1e-11);
    }
}
