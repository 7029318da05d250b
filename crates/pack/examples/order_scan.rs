//! Exploration: how the interior ψ6 of a lattice start evolves along a sequence of
//! stages, for one size distribution.
//!
//! `order_scan DIST R_OUT_MM PHI_START STAGES [SEED]`, DIST = gaussian | uniform,
//! STAGES comma-separated: `hold:SWEEPS[:EVERY]`, `grow:RATE:PHI[:EVERY]` (Monte Carlo
//! growth to bulk fraction PHI or jamming), `swaps:0|1`, `athermal:STEP[:PHI]` (swell and
//! minimise to PHI or jamming), `fill:PHI` (lattice fill, before the start).

use glam::DVec2;
use grains_analysis::fraction::bulk_fraction;
use grains_analysis::grid::CellGrid;
use grains_analysis::psi6::{order, psi6};
use grains_analysis::region::Region;
use grains_core::rng;
use grains_pack::lattice::{clearance_factor, sites};
use grains_pack::lining::lining;
use grains_pack::mc::HardDisks;
use grains_pack::relax::Soft;
use grains_pack::sizes::Distribution;
use grains_pack::spec::SizeSpec;
use rand::RngExt;

fn measure(pos: &[DVec2], radii: &[f64], fixed: usize, region: &Region) -> (f64, f64, f64) {
    let (lo, hi) = region.bounds();
    let grid = CellGrid::build(pos, lo, hi, 1.0, region.period_x());
    let psi = psi6(pos, region, &grid);
    let o = order(&psi, |k| {
        k >= fixed && region.boundary_distance(pos[k]) >= 2.0
    });
    (bulk_fraction(pos, radii, region, 2.0), o.local, o.global)
}

fn report(tag: &str, n: u64, pos: &[DVec2], radii: &[f64], fixed: usize, region: &Region) -> f64 {
    let (phi, l, g) = measure(pos, radii, fixed, region);
    println!("{tag:9} {n:7} phi {phi:.4} local {l:.3} global {g:.3}");
    phi
}

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let dist = &a[0];
    let r_out: f64 = a[1].parse().unwrap();
    let phi_start: f64 = a[2].parse().unwrap();
    let stages: Vec<Vec<String>> = a[3]
        .split(',')
        .map(|s| s.split(':').map(String::from).collect())
        .collect();
    let seed: u64 = a.get(4).map_or(1, |s| s.parse().unwrap());
    let fill: f64 = stages
        .iter()
        .find(|s| s[0] == "fill")
        .map_or(0.89, |s| s[1].parse().unwrap());
    let d0 = 95.6e-6;
    let spec = if dist == "gaussian" {
        SizeSpec::Gaussian { d0, delta: 0.113 }
    } else {
        SizeSpec::Uniform { d0, delta: 0.177 }
    };
    let sizes = Distribution::from_spec(&spec);
    let region = Region::Annulus {
        centre: DVec2::ZERO,
        r_in: 0.010 / d0,
        r_out: r_out * 1e-3 / d0,
    };
    let phase = rng::stream(seed, 1).random::<f64>();
    let lin = lining(&region, 0.6, phase);
    let fixed = lin.len();
    let mut size_rng = rng::stream(seed, 0);
    let mut place = rng::stream(seed, 2);
    let shift = DVec2::new(place.random::<f64>(), place.random::<f64>());
    let msq = sizes.mean_square() / (d0 * d0);
    let sp = (std::f64::consts::FRAC_PI_4 * msq / (fill * 0.75f64.sqrt())).sqrt();
    let r_lining = lin.iter().map(|l| l.1).fold(0.0, f64::max);
    let st = sites(&region, sp, 2.0 * r_lining + 0.5 * sp, shift);
    let mut pos: Vec<DVec2> = lin.iter().map(|l| l.0).collect();
    let mut base: Vec<f64> = lin.iter().map(|l| l.1).collect();
    pos.extend_from_slice(&st);
    base.extend(st.iter().map(|_| 0.5 * sizes.sample(&mut size_rng) / d0));
    let phi_full = bulk_fraction(&pos[fixed..], &base[fixed..], &region, 2.0);
    let s = (phi_start / phi_full).sqrt().min(1.0);
    let rad: Vec<f64> = base
        .iter()
        .enumerate()
        .map(|(i, b)| if i < fixed { *b } else { b * s })
        .collect();
    let mut soft = Soft::new(pos, rad, fixed);
    let r = soft.minimise(&region, 1e-7, 20_000);
    let f = clearance_factor(&region, &soft.pos, &soft.rad, fixed).min(1.0);
    println!(
        "{} disks, lattice fill {fill} (bulk {phi_full:.4}), FIRE {} iterations",
        st.len(),
        r.iterations
    );
    let s0 = s * f * (1.0 - 1e-12);
    let mut pos = soft.pos;
    let mut radii: Vec<f64> = base
        .iter()
        .enumerate()
        .map(|(i, b)| if i < fixed { *b } else { b * s0 })
        .collect();
    let mut swaps = true;
    let mut sweeps = 0u64;
    report("start", 0, &pos, &radii, fixed, &region);
    let t = std::time::Instant::now();
    for stage in &stages {
        match stage[0].as_str() {
            "fill" => {}
            "swaps" => swaps = stage[1] == "1",
            "hold" | "grow" => {
                let grow = stage[0] == "grow";
                let (rate, phi_end) = if grow {
                    (
                        stage[1].parse::<f64>().unwrap(),
                        stage[2].parse::<f64>().unwrap(),
                    )
                } else {
                    (0.0, 0.0)
                };
                let n: u64 = if grow {
                    u64::MAX
                } else {
                    stage[1].parse().unwrap()
                };
                let every: u64 = stage
                    .get(if grow { 3 } else { 2 })
                    .map_or(1000, |s| s.parse().unwrap());
                // Current radii as base, scale 1.
                let mut hd = HardDisks::new(
                    pos.clone(),
                    radii.clone(),
                    vec![1.0; radii.len()],
                    fixed,
                    seed + sweeps,
                );
                hd.swaps = swaps;
                let phi0 = measure(&pos, &radii, fixed, &region).0;
                let target = if grow { (phi_end / phi0).sqrt() } else { 1.0 };
                let mut last = 1.0;
                while hd.sweeps < n {
                    let st = hd.sweep(&region, rate, target);
                    if hd.sweeps.is_multiple_of(every) {
                        let (p, b, sc) = hd.state();
                        let r: Vec<f64> = b.iter().zip(&sc).map(|(b, s)| b * s).collect();
                        report(&stage[0], sweeps + hd.sweeps, &p, &r, fixed, &region);
                    }
                    if grow {
                        if st.min_scale >= target * (1.0 - 1e-9) {
                            break;
                        }
                        if hd.sweeps.is_multiple_of(200) {
                            let nominal = last * ((1.0 + rate).powi(200) - 1.0);
                            if st.mean_scale - last < 0.25 * nominal {
                                println!("jammed");
                                break;
                            }
                            last = st.mean_scale;
                        }
                    }
                }
                sweeps += hd.sweeps;
                let (p, b, sc) = hd.state();
                pos = p;
                radii = b.iter().zip(&sc).map(|(b, s)| b * s).collect();
                report("end", sweeps, &pos, &radii, fixed, &region);
            }
            "athermal" => {
                let step: f64 = stage[1].parse().unwrap();
                let phi_end: f64 = stage.get(2).map_or(1.0, |s| s.parse().unwrap());
                let cur: Vec<f64> = radii[fixed..].to_vec();
                let mut soft = Soft::new(pos.clone(), radii.clone(), fixed);
                let mut s = 1.0;
                for cycle in 0..1000 {
                    let s_next = s * (1.0 + step);
                    for (r, b) in soft.rad[fixed..].iter_mut().zip(&cur) {
                        *r = b * s_next;
                    }
                    let r = soft.minimise(&region, 1e-5, 4000);
                    let jam = r.energy > 1e-8;
                    let (phi, l, g) = measure(&soft.pos, &soft.rad, fixed, &region);
                    if cycle % 5 == 0 || jam || phi >= phi_end {
                        println!(
                            "athermal {cycle} phi {phi:.4} local {l:.3} global {g:.3} energy {:.2e}{}",
                            r.energy,
                            if jam { " jammed" } else { "" }
                        );
                    }
                    if jam || phi >= phi_end {
                        break;
                    }
                    s = s_next;
                }
                pos = soft.pos;
                radii = soft.rad;
            }
            "shrink" => {
                // Radii scaled down to bulk fraction PHI: positions (and ψ6) unchanged.
                let phi_end: f64 = stage[1].parse().unwrap();
                let phi0 = measure(&pos, &radii, fixed, &region).0;
                let k = (phi_end / phi0).sqrt();
                for r in radii[fixed..].iter_mut() {
                    *r *= k;
                }
                report("shrink", sweeps, &pos, &radii, fixed, &region);
            }
            other => panic!("unknown stage {other}"),
        }
    }
    eprintln!("{:.1} s", t.elapsed().as_secs_f64());
}
