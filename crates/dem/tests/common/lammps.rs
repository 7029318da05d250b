// The LAMMPS `pair_style granular` decks of `tests/lammps/` replayed with grains'
// granular law, in the dimension of the crate that includes this file as `dem`.
//
// Each deck's atoms start from the table's step 0 and are advanced as LAMMPS's `fix
// nve/sphere` does (half kick, drift, forces, half kick; I = 0.4 m R², 0.5 with `disc`
// in 2D), the pair forces from `dem::granular::respond`. Every table row (x, v, ω, f, τ
// of each atom) must agree with LAMMPS to 1e-10 of that field's largest magnitude in the
// run; the history too (tangential, rolling, twisting; in 2D the springs' components
// along t, LAMMPS's vectors having none along n or z).

use dem::granular::{
    respond, Contact, Damping, GranularParams, Normal, Rolling, Tangential, WIDTH,
};
use dem::math::{AngVector, Components, Vector, DIM, TAN};
use std::collections::BTreeMap;
use std::path::PathBuf;

fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../dem/tests/lammps")
}

fn csv(path: PathBuf) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split(',').map(|x| x.trim().parse().unwrap()).collect())
        .collect()
}

/// The law of one `pair_coeff` line's keywords (after the two types).
fn parse(tok: &[&str]) -> GranularParams {
    let f = |k: usize| tok[k].parse::<f64>().unwrap();
    let normal = match tok[0] {
        "hooke" => Normal::Hooke,
        "hertz/material" => Normal::HertzMaterial,
        other => panic!("normal model {other}"),
    };
    let (stiffness, damp_in) = (f(1), f(2));
    let mut k = 3;
    let poisson = if normal == Normal::HertzMaterial {
        k += 1;
        f(3)
    } else {
        0.0
    };
    let mut damping = Damping::Viscoelastic;
    let mut tangential = None;
    let mut rolling = None;
    let (mut twisting, mut limit_damping) = (false, false);
    while k < tok.len() {
        match tok[k] {
            "damping" => {
                damping = match tok[k + 1] {
                    "velocity" => Damping::Velocity,
                    "mass_velocity" => Damping::MassVelocity,
                    "viscoelastic" => Damping::Viscoelastic,
                    "tsuji" => Damping::Tsuji,
                    other => panic!("damping {other}"),
                };
                k += 2;
            }
            "tangential" => {
                let model = match tok[k + 1] {
                    "linear_history" => Tangential::LinearHistory,
                    "mindlin" => Tangential::Mindlin,
                    "mindlin_rescale" => Tangential::MindlinRescale,
                    other => panic!("tangential {other}"),
                };
                let kt = (tok[k + 2] != "NULL").then(|| f(k + 2));
                tangential = Some((model, kt, f(k + 3), f(k + 4)));
                k += 5;
            }
            "rolling" => {
                assert_eq!(tok[k + 1], "sds");
                rolling = Some(Rolling {
                    kr: f(k + 2),
                    gamma_r: f(k + 3),
                    mu_r: f(k + 4),
                });
                k += 5;
            }
            "twisting" => {
                assert_eq!(tok[k + 1], "marshall");
                twisting = true;
                k += 2;
            }
            "limit_damping" => {
                limit_damping = true;
                k += 1;
            }
            other => panic!("keyword {other}"),
        }
    }
    let (model, kt, x_gamma_t, mu) = tangential.expect("a tangential model");
    GranularParams {
        rolling,
        twisting,
        limit_damping,
        ..GranularParams::lammps(
            normal, stiffness, damping, damp_in, poisson, model, kt, x_gamma_t, mu,
        )
    }
}

struct Deck {
    laws: BTreeMap<(usize, usize), GranularParams>,
    dt: f64,
    steps: usize,
    inertia: f64,
}

fn deck(name: &str) -> Deck {
    let text = std::fs::read_to_string(dir().join("decks").join(format!("{name}.in"))).unwrap();
    let mut d = Deck {
        laws: BTreeMap::new(),
        dt: 0.0,
        steps: 0,
        inertia: 0.4,
    };
    for line in text.lines() {
        let t: Vec<&str> = line.split_whitespace().collect();
        match t.first() {
            Some(&"pair_coeff") => {
                let ty = |s: &str| if s == "*" { 0 } else { s.parse().unwrap() };
                d.laws.insert((ty(t[1]), ty(t[2])), parse(&t[3..]));
            }
            Some(&"timestep") => d.dt = t[1].parse().unwrap(),
            Some(&"run") => d.steps = t[1].parse().unwrap(),
            Some(&"fix") if t[3] == "nve/sphere" && t.contains(&"disc") => d.inertia = 0.5,
            _ => {}
        }
    }
    d
}

impl Deck {
    fn law(&self, a: usize, b: usize) -> &GranularParams {
        self.laws
            .get(&(0, 0))
            .or_else(|| self.laws.get(&(a.min(b), a.max(b))))
            .expect("a law for the pair")
    }
}

#[derive(Clone)]
struct Atom {
    kind: usize,
    r: f64,
    m: f64,
    x: Vector,
    v: Vector,
    w: AngVector,
    f: Vector,
    t: AngVector,
}

/// One table row's fields (x, v, ω, f, τ) as this dimension holds them.
fn fields(row: &[f64]) -> [Vec<f64>; 5] {
    let vec = |at: usize| row[at..at + DIM].to_vec();
    let ang = |end: usize| row[end - AngVector::N..end].to_vec();
    [vec(2), vec(5), ang(11), vec(11), ang(17)]
}

fn forces(d: &Deck, atoms: &mut [Atom], hist: &mut BTreeMap<(usize, usize), [f64; WIDTH]>, update: bool) {
    for a in atoms.iter_mut() {
        a.f = Vector::default();
        a.t = AngVector::default();
    }
    for i in 0..atoms.len() {
        for j in i + 1..atoms.len() {
            let (ai, aj) = (&atoms[i], &atoms[j]);
            let dx = aj.x - ai.x;
            let rsum = ai.r + aj.r;
            if dx.length_squared() >= rsum * rsum {
                hist.remove(&(i, j));
                continue;
            }
            let dist = dx.length();
            let c = Contact {
                n: dx / dist,
                overlap: rsum - dist,
                r_eff: ai.r * aj.r / rsum,
                m_eff: ai.m * aj.m / (ai.m + aj.m),
                v: ai.v - aj.v,
                spin: ai.r * ai.w + aj.r * aj.w,
                w_rel: ai.w - aj.w,
            };
            let h = hist.entry((i, j)).or_insert([0.0; WIDTH]);
            let resp = respond(d.law(ai.kind, aj.kind), &c, h, d.dt, update);
            let (arm_i, arm_j) = (ai.r - 0.5 * c.overlap, aj.r - 0.5 * c.overlap);
            atoms[i].f += resp.force;
            atoms[i].t += arm_i * resp.moment + resp.couple;
            atoms[j].f -= resp.force;
            atoms[j].t += arm_j * resp.moment - resp.couple;
        }
    }
}

/// Replays `name` and returns the largest deviation from LAMMPS over the table, relative
/// to each field's largest magnitude, and the largest history deviation.
fn replay(name: &str) -> (f64, f64) {
    let d = deck(name);
    let table = csv(dir().join("tables").join(format!("{name}.csv")));
    let info = csv(dir().join("tables").join(format!("{name}.atoms.csv")));
    let mut atoms: Vec<Atom> = info
        .iter()
        .map(|a| {
            let row = table
                .iter()
                .find(|r| r[0] == 0.0 && r[1] == a[0])
                .expect("step 0 of every atom");
            let [x, v, w, _, _] = fields(row);
            Atom {
                kind: a[1] as usize,
                r: a[2],
                m: a[3],
                x: Vector::from_slice(&x),
                v: Vector::from_slice(&v),
                w: AngVector::from_slice(&w),
                f: Vector::default(),
                t: AngVector::default(),
            }
        })
        .collect();
    let scale = scales(&table);
    let history = csv(dir().join("tables").join(format!("{name}.history.csv")));
    let hscale = history
        .iter()
        .flat_map(|r| r[3..].iter())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let mut hist = BTreeMap::new();
    let (dtf, dt) = (0.5 * d.dt, d.dt);
    forces(&d, &mut atoms, &mut hist, false);
    let (mut worst, mut worst_h) = (0.0f64, 0.0f64);
    for step in 0..=d.steps {
        if step > 0 {
            for a in atoms.iter_mut() {
                a.v += (dtf / a.m) * a.f;
                a.x += dt * a.v;
                a.w += (dtf / d.inertia) / (a.r * a.r * a.m) * a.t;
            }
            forces(&d, &mut atoms, &mut hist, true);
            for a in atoms.iter_mut() {
                a.v += (dtf / a.m) * a.f;
                a.w += (dtf / d.inertia) / (a.r * a.r * a.m) * a.t;
            }
        }
        for row in table.iter().filter(|r| r[0] == step as f64) {
            let a = &atoms[row[1] as usize - 1];
            let ours = [
                Vector::flatten(&[a.x]),
                Vector::flatten(&[a.v]),
                AngVector::flatten(&[a.w]),
                Vector::flatten(&[a.f]),
                AngVector::flatten(&[a.t]),
            ];
            for ((o, l), s) in ours.iter().zip(fields(row)).zip(scale) {
                for (x, y) in o.iter().zip(&l) {
                    worst = worst.max((x - y).abs() / s);
                }
            }
        }
        if DIM == 3 {
            for row in history.iter().filter(|r| r[0] == step as f64) {
                let (i, j) = (row[1] as usize - 1, row[2] as usize - 1);
                let h = hist.get(&(i, j)).expect("a contact LAMMPS has");
                let rescale = row.len() == 11;
                // Columns: t0..t2 [a_prev] r0..r2 tw; ours: t (TAN), a_prev, r (TAN), tw.
                let theirs: Vec<f64> = if rescale {
                    row[3..].to_vec()
                } else {
                    let mut v = row[3..6].to_vec();
                    v.push(h[TAN]);
                    v.extend_from_slice(&row[6..]);
                    v
                };
                for (k, (x, y)) in h.iter().zip(&theirs).enumerate() {
                    if k != TAN {
                        worst_h = worst_h.max((x - y).abs() / hscale);
                    }
                }
            }
        } else {
            for row in history.iter().filter(|r| r[0] == step as f64) {
                let (i, j) = (row[1] as usize - 1, row[2] as usize - 1);
                let h = hist.get(&(i, j)).expect("a contact LAMMPS has");
                // LAMMPS keeps the springs as vectors in the xy plane; ours are their
                // components along t = (−n_y, n_x), n from i to j. Columns: t0 t1 t2
                // [a_prev] r0 r1 r2.
                let n = Vector::flatten(&[(atoms[j].x - atoms[i].x).normalize()]);
                let (t, normal) = ([-n[1], n[0]], [n[0], n[1]]);
                let along = |at: usize, u: [f64; 2]| row[at] * u[0] + row[at + 1] * u[1];
                let roll = if row.len() == 11 { 7 } else { 6 };
                let mut pairs = vec![(h[0], along(3, t)), (0.0, along(3, normal)), (0.0, row[5])];
                if row.len() > roll {
                    let r = h[TAN + 1];
                    pairs.extend([(r, along(roll, t)), (0.0, along(roll, normal)), (0.0, row[roll + 2])]);
                }
                for (x, y) in pairs {
                    worst_h = worst_h.max((x - y).abs() / hscale);
                }
            }
        }
    }
    (worst, worst_h)
}

/// Runs deck `name` through the engine itself (`State::new`, `step`, the granular law in
/// `Setup::granular`); returns the largest deviation from LAMMPS of any field.
fn engine(name: &str) -> f64 {
    use dem::{step, ContactModel, Domain, Material, Particles, PairTable, Setup, State};
    let d = deck(name);
    let info = csv(dir().join("tables").join(format!("{name}.atoms.csv")));
    let table = csv(dir().join("tables").join(format!("{name}.csv")));
    let types = info.iter().map(|a| a[1] as usize).max().unwrap();
    let material = |k: usize| Material {
        name: format!("type{k}"),
        density: 1.0,
        youngs: None,
        poisson: None,
        restitution: None,
        friction: None,
        inertia_factor: d.inertia,
    };
    let domain = Domain {
        lo: Vector::splat(-1.0),
        hi: Vector::splat(1.0),
        periodic: [false; DIM],
    };
    let model = ContactModel::unused();
    let materials = (1..=types).map(material).collect();
    let mut setup = Setup::new(domain, materials, model, Vec::new(), Vector::ZERO, 1e-3).unwrap();
    setup.granular = Some(PairTable::from_fn(types, |a, b| *d.law(a + 1, b + 1)));
    let mut p = Particles::default();
    for a in &info {
        let row = table.iter().find(|r| r[0] == 0.0 && r[1] == a[0]).unwrap();
        let [x, v, w, _, _] = fields(row);
        let (r, m) = (a[2], a[3]);
        let kind = a[1] as u16 - 1;
        p.push(Vector::from_slice(&x), r, 1.0, d.inertia, kind, Vector::from_slice(&v), AngVector::from_slice(&w));
        // LAMMPS's own mass (ρ 4/3 π R³, also in 2D) and moment of inertia.
        let i = p.len() - 1;
        p.inv_mass[i] = 1.0 / m;
        p.inv_inertia[i] = 1.0 / (d.inertia * m * r * r);
    }
    let scale = scales(&table);
    let mut st = State::new(&setup, p);
    let mut worst = 0.0f64;
    for n in 0..=d.steps {
        if n > 0 {
            step(&setup, &mut st, d.dt);
        }
        worst = worst.max(deviation(&st.particles, &table, n, &scale));
    }
    worst
}

/// Each field's largest magnitude over a table (x, v, ω, f, τ).
fn scales(table: &[Vec<f64>]) -> [f64; 5] {
    let mut scale = [0.0f64; 5];
    for row in table {
        for (s, f) in scale.iter_mut().zip(fields(row)) {
            *s = f.iter().fold(*s, |m, v| m.max(v.abs()));
        }
    }
    scale
}

/// The largest difference between the engine's particles and the table's rows of step
/// `n` (atoms by id, from 1), relative to each field's `scale`.
fn deviation(p: &dem::Particles, table: &[Vec<f64>], n: usize, scale: &[f64; 5]) -> f64 {
    let mut worst = 0.0f64;
    for row in table.iter().filter(|r| r[0] == n as f64) {
        let i = p.id.iter().position(|&k| k as f64 == row[1] - 1.0).unwrap();
        let ours = [
            Vector::flatten(&[p.pos[i]]),
            Vector::flatten(&[p.vel[i]]),
            AngVector::flatten(&[p.omega[i]]),
            Vector::flatten(&[p.force[i]]),
            AngVector::flatten(&[p.torque[i]]),
        ];
        for ((o, l), s) in ours.iter().zip(fields(row)).zip(scale) {
            for (x, y) in o.iter().zip(&l) {
                worst = worst.max((x - y).abs() / s);
            }
        }
    }
    worst
}

fn check(name: &str) {
    let through_engine = engine(name);
    assert!(
        through_engine < 1e-10,
        "{name}: the engine differs from LAMMPS by {through_engine:e}"
    );
    let (fields, history) = replay(name);
    assert!(fields < 1e-10, "{name}: fields differ from LAMMPS by {fields:e}");
    assert!(history < 1e-10, "{name}: history differs from LAMMPS by {history:e}");
}
