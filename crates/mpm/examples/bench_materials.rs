//! The `grains bench mpm` set-up (a block of N points falling at 1 m/s in a walled unit
//! box under gravity, G × G cells, Δt = 2·10⁻⁴·128/G, 50 warm-up steps) with a choice of
//! material, to compare the cost of the models with memory against the elastic one:
//!
//! `cargo run --release -p grains-mpm --example bench_materials -- --material j2
//!  [--particles 32768] [--grid 128] [--steps 500] [--warmup 50] [--shape bspline2]
//!  [--update usl] [--threads 1]`
//!
//! The block reaches the floor after ~1000 steps at G = 128: `--warmup 1000` times the
//! impact, where the J2 block yields.
//!
//! Materials (all with K = 200, G (instantaneous) = 100, ρ = 1, so the same time step):
//! `elastic`; `j2` (σ_y = 5, H = 10: the impact on the floor yields the block);
//! `maxwell` (G∞ = 50 and two Prony terms, 30 and 20 with τ = 0.01 and 0.1 s);
//! `maxwell4` (G∞ = 40, four terms of 15); `thermal` (elastic, α = 10⁻⁴, heated at
//! 100 per second); `neo_hookean`.

use glam::DVec2;
use grains_mpm::*;
use std::time::Instant;

fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let rest = stat.rfind(')').map_or("", |k| &stat[k + 2..]);
    let f: Vec<f64> = rest
        .split_whitespace()
        .skip(11)
        .take(2)
        .filter_map(|x| x.parse().ok())
        .collect();
    f.iter().sum::<f64>() / 100.0
}

fn material(name: &str) -> (Material, Option<TemperatureHistory>) {
    let (density, bulk, shear) = (1.0, 200.0, 100.0);
    let elastic = |expansion| Material::LinearElastic {
        name: name.into(),
        density,
        bulk,
        shear,
        expansion,
    };
    let prony = |terms: &[(f64, f64)]| {
        terms
            .iter()
            .map(|&(shear, time)| PronyTerm { shear, time })
            .collect()
    };
    match name {
        "elastic" => (elastic(0.0), None),
        "thermal" => (
            elastic(1e-4),
            Some(TemperatureHistory::Rate {
                initial: 0.0,
                rate: 100.0,
            }),
        ),
        "neo_hookean" => (
            Material::NeoHookean {
                name: name.into(),
                density,
                bulk,
                shear,
            },
            None,
        ),
        "j2" => (
            Material::J2Plastic {
                name: name.into(),
                density,
                bulk,
                shear,
                yield_stress: 5.0,
                hardening: 10.0,
                expansion: 0.0,
            },
            None,
        ),
        "maxwell" => (
            Material::Maxwell {
                name: name.into(),
                density,
                bulk,
                shear: 50.0,
                prony: prony(&[(30.0, 0.01), (20.0, 0.1)]),
                expansion: 0.0,
            },
            None,
        ),
        "maxwell4" => (
            Material::Maxwell {
                name: name.into(),
                density,
                bulk,
                shear: 40.0,
                prony: prony(&[(15.0, 0.001), (15.0, 0.01), (15.0, 0.1), (15.0, 1.0)]),
                expansion: 0.0,
            },
            None,
        ),
        m => panic!(
            "--material = {m}: must be elastic, thermal, neo_hookean, j2, maxwell or maxwell4"
        ),
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let opt = |key: &str, default: &str| -> String {
        args.iter()
            .position(|a| a == key)
            .and_then(|k| args.get(k + 1))
            .cloned()
            .unwrap_or_else(|| default.into())
    };
    let n: usize = opt("--particles", "32768").parse().unwrap();
    let cells: usize = opt("--grid", "128").parse().unwrap();
    let steps: u64 = opt("--steps", "500").parse().unwrap();
    let warmup: u64 = opt("--warmup", "50").parse().unwrap();
    let threads: usize = opt("--threads", "1").parse().unwrap();
    let mat = opt("--material", "elastic");
    let shape = match opt("--shape", "bspline2").as_str() {
        "linear" => ShapeFunction::Linear,
        "gimp" => ShapeFunction::Gimp,
        _ => ShapeFunction::Bspline2,
    };
    let scheme = match opt("--update", "usl").as_str() {
        "usf" => UpdateScheme::Usf,
        "usavg" => UpdateScheme::Usavg,
        "musl" => UpdateScheme::Musl,
        _ => UpdateScheme::Usl,
    };
    let (m, temperature) = material(&mat);
    let h = 1.0 / cells as f64;
    let nx = (n as f64).sqrt().ceil() as usize;
    let ny = n.div_ceil(nx);
    let pitch = DVec2::new(0.4 / nx as f64, 0.4 / ny as f64);
    let vol = 0.16 / n as f64;
    let mut p = Particles::default();
    for k in 0..n {
        let (i, j) = (k % nx, k / nx);
        let x = DVec2::new(0.2, 0.2) + pitch * DVec2::new(i as f64 + 0.5, j as f64 + 0.5);
        p.push(0, vol, vol, x, DVec2::new(0.0, -1.0));
    }
    let setup = Setup {
        grid: Grid {
            lo: DVec2::ZERO,
            h,
            cells: [cells, cells],
        },
        shape,
        half_width: (0.5 * pitch.max_element() / h).min(0.5),
        scheme,
        flip: 1.0,
        pass1_to_particles: true,
        materials: vec![m],
        bodies: vec![Body {
            temperature,
            ..Body::free("block", 0)
        }],
        contact: ContactTable::new(1, ContactLaw::Coulomb { mu: 0.3 }),
        separation: None,
        walls: [Some(0.0); 4],
        gravity: DVec2::new(0.0, -9.8),
    };
    let dt = 2e-4 * 128.0 / cells as f64;
    setup.validate().unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut s = State::new(&setup, p);
        let mut w = Solver::new(&setup, &mut s);
        for _ in 0..warmup {
            step(&setup, &mut s, &mut w, dt).unwrap();
        }
        let (c0, t0) = (cpu_seconds(), Instant::now());
        rayon::scope(|_| {
            for _ in 0..steps {
                step(&setup, &mut s, &mut w, dt).unwrap();
            }
        });
        let (cpu, wall) = (cpu_seconds() - c0, t0.elapsed().as_secs_f64());
        let d = diagnostics::measure(&setup, &s.particles, &w.layout().bodies);
        println!(
            "material {mat}: {n} points, {cells}² cells, {steps} steps, {threads} thread(s): \
             wall {wall:.3} s, cpu {cpu:.3} s, {:.4e} particle-steps per cpu-s; \
             dissipated {:.3e} J/m, max plastic strain {:.3e}",
            n as f64 * steps as f64 / cpu,
            d.dissipated,
            d.bodies[0].plastic_max
        );
    });
}
