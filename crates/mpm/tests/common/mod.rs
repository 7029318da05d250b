//! Helpers shared by the engine-level tests: set-ups on a grid, lattice fills, stepping.
#![allow(dead_code)]

use glam::DVec2;
use grains_mpm::*;

/// A set-up and the step a test takes with it.
pub struct Case {
    /// The set-up.
    pub setup: Setup,
    /// The time step (s).
    pub dt: f64,
}

impl std::ops::Deref for Case {
    type Target = Setup;
    fn deref(&self) -> &Setup {
        &self.setup
    }
}

impl std::ops::DerefMut for Case {
    fn deref_mut(&mut self) -> &mut Setup {
        &mut self.setup
    }
}

/// A set-up with GIMP, USAVG, FLIP, frictionless default contact with the separation test,
/// no walls and no gravity; `dt` is `safety` × the stable step.
pub fn setup(
    lo: [f64; 2],
    h: f64,
    cells: [usize; 2],
    materials: Vec<Material>,
    bodies: Vec<Body>,
    safety: f64,
) -> Case {
    let n = bodies.len();
    let shape = ShapeFunction::Gimp;
    let s = Setup {
        grid: Grid {
            lo: DVec2::from(lo),
            h,
            cells,
            periodic_y: false,
        },
        shape,
        half_width: 0.25,
        scheme: UpdateScheme::Usavg,
        flip: 1.0,
        pass1_to_particles: true,
        materials,
        bodies,
        contact: ContactTable::new(n, ContactLaw::Coulomb { mu: 0.0 }),
        crowd: Default::default(),
        separation: Some(contact::touching_separation(shape, 2) * 1.05 * h),
        walls: [None; 4],
        gravity: DVec2::ZERO,
        ledger: false,
    };
    s.validate().unwrap();
    let dt = safety * timestep::critical_dt(&s, &Particles::default());
    Case { setup: s, dt }
}

/// Fills `g` on the grid's 2 × 2 lattice with body `b` at velocity `v(x)`, volumes scaled
/// to the exact area.
pub fn fill(p: &mut Particles, setup: &Setup, b: u16, g: &Geometry, v: impl Fn(DVec2) -> DVec2) {
    let pts = g.fill(setup.grid.lo, 0.5 * setup.grid.h);
    let vol = g.area() / pts.len() as f64;
    let rho = setup.materials[setup.bodies[b as usize].material].density();
    for x in pts {
        p.push(b, rho * vol, vol, x, v(x));
    }
}

/// A state and its solver at t = 0.
pub fn start(setup: &Setup, p: Particles) -> (State, Solver) {
    let mut s = State::new(setup, p);
    let w = Solver::new(setup, &mut s);
    (s, w)
}

/// Steps until `t_end`, calling `watch` after every step.
pub fn run_until(
    setup: &Case,
    s: &mut State,
    w: &mut Solver,
    t_end: f64,
    mut watch: impl FnMut(&State, &Solver),
) {
    while s.time < t_end - 0.5 * setup.dt {
        step(setup, s, w, setup.dt).unwrap();
        watch(s, w);
    }
}

/// Mean of `f` over the points of body `b` that satisfy `keep`.
pub fn mean(s: &State, b: u16, keep: impl Fn(usize) -> bool, f: impl Fn(usize) -> f64) -> f64 {
    let p = &s.particles;
    let (mut sum, mut n) = (0.0, 0usize);
    for i in 0..p.len() {
        if p.body[i] == b && keep(i) {
            sum += f(i);
            n += 1;
        }
    }
    assert!(n > 0, "no point selected");
    sum / n as f64
}

/// Least-squares slope and intercept of y(x).
pub fn fit(x: &[f64], y: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    let slope = sxy / sxx;
    (slope, my - slope * mx)
}

/// A temperature going from 0 to `change` along a smoothstep u²(3 − 2u) over `[0, ramp]`
/// (41 table points), then held.
pub fn smoothstep(ramp: f64, change: f64) -> TemperatureHistory {
    let points = (0..=40)
        .map(|k| {
            let u = k as f64 / 40.0;
            [u * ramp, change * u * u * (3.0 - 2.0 * u)]
        })
        .collect();
    TemperatureHistory::Table { points }
}
