//! Quick experiment: the Bardenhagen (1998) cylinder bounce, printing energy and body
//! kinematics. `cargo run --release -p grains-mpm --example bounce -- [cells_per_d] [mu]
//! [shape] [scheme] [pass1] [cfl]`.

use glam::DVec2;
use grains_mpm::diagnostics::measure;
use grains_mpm::*;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let per_d: usize = a.get(1).map_or(8, |s| s.parse().unwrap());
    let mu: f64 = a.get(2).map_or(0.0, |s| s.parse().unwrap());
    let shape = match a.get(3).map_or("gimp", |s| s.as_str()) {
        "linear" => ShapeFunction::Linear,
        "bspline2" => ShapeFunction::Bspline2,
        _ => ShapeFunction::Gimp,
    };
    let scheme = match a.get(4).map_or("usf", |s| s.as_str()) {
        "usl" => UpdateScheme::Usl,
        "musl" => UpdateScheme::Musl,
        "usavg" => UpdateScheme::Usavg,
        _ => UpdateScheme::Usf,
    };
    let pass1 = a.get(5).is_some_and(|s| s == "1");
    let cfl: f64 = a.get(6).map_or(0.2, |s| s.parse().unwrap());
    let h = 1.0 / per_d as f64;
    let cells = 3 * per_d;
    let mat = Material::LinearElastic {
        name: "m".into(),
        density: 1.0,
        bulk: 1.0,
        shear: 0.5,
        expansion: 0.0,
    };
    let c = mat.wave_speed();
    let setup = Setup {
        grid: Grid {
            lo: DVec2::ZERO,
            h,
            cells: [cells, cells],
            periodic_y: false,
        },
        shape,
        half_width: 0.25,
        scheme,
        flip: 1.0,
        pass1_to_particles: pass1,
        materials: vec![mat],
        bodies: vec![Body::free("cyl", 0)],
        contact: ContactTable::new(1, ContactLaw::Coulomb { mu: 0.0 }),
        crowd: Default::default(),
        separation: None,
        walls: [Some(mu); 4],
        gravity: DVec2::ZERO,
        ledger: false,
    };
    let dt = cfl * h / (c + 0.15);
    let geo = Geometry::Disk {
        centre: [1.0, 1.5],
        radius: 0.5,
    };
    let pts = geo.fill(DVec2::ZERO, h / 2.0);
    let vol = geo.area() / pts.len() as f64;
    let mut p = Particles::default();
    for x in pts {
        p.push(0, vol, vol, x, DVec2::new(0.1, 0.1));
    }
    let mut s = State {
        particles: p,
        ..Default::default()
    };
    let mut w = Solver::new(&setup, &mut s);
    let t_end: f64 = std::env::var("TEND")
        .ok()
        .map_or(34.0, |s| s.parse().unwrap());
    let steps = (t_end / dt) as u64;
    let every = std::env::var("EVERY")
        .ok()
        .map_or((steps / 68).max(1), |s| s.parse().unwrap());
    let t0 = std::time::Instant::now();
    let mut angle = 0.0;
    let mut last = 0.0;
    let mut e0 = 0.0;
    for k in 0..=steps {
        if k > 0 {
            step(&setup, &mut s, &mut w, dt).unwrap();
        }
        if k % every == 0 {
            let d = measure(&setup, &s.particles, &w.layout().bodies);
            let b = d.bodies[0];
            let mut da = b.angle - last;
            da -= (da / std::f64::consts::TAU).round() * std::f64::consts::TAU;
            angle += da;
            last = b.angle;
            if k == 0 {
                e0 = d.total();
            }
            println!(
                "t {:6.2} E {:.6} ({:+.3}%) ke {:.6} se {:.6} |p| {:.5} v ({:+.4},{:+.4}) w {:+.4} ang {:+.3}deg walls {:?}",
                s.time,
                d.total(),
                100.0 * (d.total() / e0 - 1.0),
                d.kinetic,
                d.strain,
                d.momentum.length(),
                b.velocity.x,
                b.velocity.y,
                b.omega,
                angle.to_degrees(),
                s.touch[0].walls
            );
        }
    }
    eprintln!("{} steps in {:.2?}", steps, t0.elapsed());
}
