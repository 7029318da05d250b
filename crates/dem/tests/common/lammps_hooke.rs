// The LAMMPS `pair_style gran/hooke/history` decks of `tests/lammps/hooke/` run by the
// engine itself (`State::new`, `step`) with the `hooke_history` contact model, in the
// dimension of the crate that includes this file as `dem`: positions, velocities, spins,
// forces and torques of every atom must follow LAMMPS to a bound (1e-10 in 3D) of each
// field's largest magnitude over the run. The including file defines `floor()`, the wall
// z = 0 (3D), and includes `lammps.rs` first, whose table readers this file uses.

use super::{csv, deviation, scales};
use dem::math::{AngVector, Components, Vector, DIM};
use dem::{step, ContactModel, Domain, Material, Particles, Setup, State, Wall};
use std::path::PathBuf;

fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../dem/tests/lammps/hooke")
}

/// The contact model of a `gran/hooke/history kn kt γn γt xmu 1` argument list.
fn model(args: &[&str]) -> ContactModel {
    let f = |k: usize| args[k].parse::<f64>().unwrap();
    assert_eq!(args[5], "1", "dampflag 1");
    ContactModel::HookeHistory {
        kn: f(0),
        kt: f(1),
        gamma_n: f(2),
        gamma_t: f(3),
        mu: f(4),
        limit_damping: false,
    }
}

/// Runs deck `name` through the engine; returns the largest deviation from LAMMPS.
fn replay(name: &str) -> f64 {
    let text = std::fs::read_to_string(dir().join("decks").join(format!("{name}.in"))).unwrap();
    let (mut pair, mut wall, mut dt, mut steps, mut inertia) = (None, None, 0.0, 0, 0.4);
    for line in text.lines() {
        let t: Vec<&str> = line.split_whitespace().collect();
        match t.first() {
            Some(&"pair_style") => pair = Some(model(&t[2..])),
            Some(&"fix") if t[3] == "wall/gran" => {
                assert_eq!(&t[11..], ["zplane", "0.0", "NULL"]);
                wall = Some(model(&t[5..11]));
            }
            Some(&"fix") if t[3] == "nve/sphere" && t.contains(&"disc") => inertia = 0.5,
            Some(&"timestep") => dt = t[1].parse().unwrap(),
            Some(&"run") => steps = t[1].parse().unwrap(),
            _ => {}
        }
    }
    // A deck with a wall has one sphere: the wall's law is the only one it meets.
    let walls: Vec<Wall> = match wall {
        Some(_) => vec![Wall {
            name: "floor".into(),
            shape: floor(),
            material: None,
            motion: Default::default(),
        }],
        None => Vec::new(),
    };
    let law = wall.or(pair).expect("a contact law");
    let atoms = csv(dir().join("tables").join(format!("{name}.atoms.csv")));
    let material = Material {
        name: "m".into(),
        density: atoms[0][2],
        youngs: None,
        poisson: None,
        restitution: None,
        friction: None,
        inertia_factor: inertia,
    };
    let domain = Domain {
        lo: Vector::splat(-1.0),
        hi: Vector::splat(1.0),
        periodic: [false; DIM],
    };
    let setup = Setup::new(domain, vec![material], law, walls, Vector::ZERO, 1e-3).unwrap();
    let mut p = Particles::default();
    for a in &atoms {
        let (r, m) = (a[1], a[3]);
        p.push(
            Vector::from_slice(&a[4..4 + DIM]),
            r,
            a[2],
            inertia,
            0,
            Vector::from_slice(&a[7..7 + DIM]),
            AngVector::from_slice(&a[13 - AngVector::N..13]),
        );
        // LAMMPS's own mass (ρ 4/3 π R³, also in 2D) and moment of inertia.
        let i = p.len() - 1;
        p.inv_mass[i] = 1.0 / m;
        p.inv_inertia[i] = 1.0 / (inertia * m * r * r);
    }
    let table = csv(dir().join("tables").join(format!("{name}.csv")));
    let scale = scales(&table);
    let mut st = State::new(&setup, p);
    let mut worst = 0.0f64;
    for n in 0..=steps {
        if n > 0 {
            step(&setup, &mut st, dt);
        }
        worst = worst.max(deviation(&st.particles, &table, n, &scale));
    }
    worst
}

fn check(name: &str, bound: f64) {
    let worst = replay(name);
    assert!(worst < bound, "{name}: differs from LAMMPS by {worst:e}");
}
