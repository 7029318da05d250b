//! Exploration: interior ψ6 of a packing file under several neighbour definitions.
//! `cargo run --release -p grains-analysis --example psi6_defs -- FILE`

use glam::DVec2;
use grains_analysis::grid::CellGrid;
use grains_analysis::psi6::nearest;
use grains_analysis::sample::load;

fn main() {
    let path = std::env::args().nth(1).unwrap();
    let s = load(path.as_ref()).unwrap();
    let region = s.region.unwrap();
    let n = s.pos.len();
    let d0 = 2.0 * s.radius[s.lining..].iter().sum::<f64>() / (n - s.lining) as f64;
    let (lo, hi) = region.bounds();
    let grid = CellGrid::build(&s.pos, lo, hi, 2.5 * d0, region.period_x());
    let interior: Vec<bool> = (0..n)
        .map(|k| k >= s.lining && region.boundary_distance(s.pos[k]) >= 2.0 * d0)
        .collect();
    // Candidates: 12 nearest by centre.
    let defs = [
        "6nn_centre",
        "6nn_gap",
        "contacts_1e-3",
        "contacts_2e-2",
        "cut_1.2sum",
        "cut_1.3d0",
    ];
    let mut sums = vec![(DVec2::ZERO, 0.0f64, 0usize, 0.0f64); defs.len()];
    for k in (0..n).filter(|&k| interior[k]) {
        let cand = nearest(&s.pos, &region, &grid, k, 14);
        let info: Vec<(f64, f64, f64)> = cand
            .iter()
            .map(|&(d2, j)| {
                let j = j as usize;
                let dv = region.delta(s.pos[k], s.pos[j]);
                let d = d2.sqrt();
                (d, d - s.radius[k] - s.radius[j], dv.y.atan2(dv.x))
            })
            .collect();
        let mut bygap = info.clone();
        bygap.sort_by(|a, b| a.1.total_cmp(&b.1));
        let sets: Vec<Vec<f64>> = vec![
            info.iter().take(6).map(|x| x.2).collect(),
            bygap.iter().take(6).map(|x| x.2).collect(),
            info.iter()
                .filter(|x| x.1 <= 1e-3 * d0)
                .map(|x| x.2)
                .collect(),
            info.iter()
                .filter(|x| x.1 <= 2e-2 * d0)
                .map(|x| x.2)
                .collect(),
            info.iter()
                .filter(|x| x.0 <= 1.2 * (x.0 - x.1))
                .map(|x| x.2)
                .collect(),
            info.iter()
                .filter(|x| x.0 <= 1.3 * d0)
                .map(|x| x.2)
                .collect(),
        ];
        for (m, set) in sets.iter().enumerate() {
            if set.is_empty() {
                continue;
            }
            let mut z = DVec2::ZERO;
            for t in set {
                z += DVec2::new((6.0 * t).cos(), (6.0 * t).sin());
            }
            z /= set.len() as f64;
            sums[m].0 += z;
            sums[m].1 += z.length();
            sums[m].2 += 1;
            sums[m].3 += set.len() as f64;
        }
    }
    for (m, d) in defs.iter().enumerate() {
        let (z, l, c, nn) = sums[m];
        println!(
            "{d:14} local {:.3} global {:.3} mean n {:.2} ({} particles)",
            l / c as f64,
            (z / c as f64).length(),
            nn / c as f64,
            c
        );
    }
}
