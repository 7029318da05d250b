//! A quick built-in particle ring: a triangular lattice of polydisperse disks between
//! two chains of small lining disks tangent to the ring's circles. It stands in for a
//! `grains pack` packing in small examples and tests: no overlaps, an area fraction of
//! about 0.9069·⟨d²⟩/(d0(1 + spread))² (≈ 0.85 for spread = 0.03), built in O(N).

use glam::DVec2;
use grains_core::rng;
use rand::RngExt;
use std::f64::consts::TAU;

/// Disks of a ring (centres and radii, m).
#[derive(Clone, Debug, Default)]
pub struct RingDisks {
    /// Centres.
    pub pos: Vec<DVec2>,
    /// Radii.
    pub radius: Vec<f64>,
}

/// Builds the ring between `r_in` and `r_out` about `centre`.
pub fn lattice_ring(
    centre: DVec2,
    r_in: f64,
    r_out: f64,
    d0: f64,
    spread: f64,
    lining: f64,
    seed: u64,
) -> RingDisks {
    let mut out = RingDisks::default();
    let r_line = 0.5 * lining * d0;
    let gap = 1e-6 * d0;
    let mut inner_edge = r_in;
    let mut outer_edge = r_out;
    if lining > 0.0 {
        for (rc, sign) in [(r_in + r_line, 1.0), (r_out - r_line, -1.0)] {
            // As many disks as fit around the circle of centres without touching.
            let n = (TAU / (2.0 * (r_line / rc).asin() * (1.0 + 1e-9))).floor() as usize;
            for k in 0..n {
                let a = TAU * k as f64 / n as f64;
                out.pos.push(centre + rc * DVec2::new(a.cos(), a.sin()));
                out.radius.push(r_line);
            }
            if sign > 0.0 {
                inner_edge = rc + r_line + gap;
            } else {
                outer_edge = rc - r_line - gap;
            }
        }
    }
    let pitch = d0 * (1.0 + spread) + gap;
    let row = pitch * 0.5 * 3f64.sqrt();
    let ny = (outer_edge / row).ceil() as i64 + 1;
    let nx = (outer_edge / pitch).ceil() as i64 + 1;
    let mut rng = rng::seeded(seed);
    for j in -ny..=ny {
        let shift = if j.rem_euclid(2) == 1 {
            0.5 * pitch
        } else {
            0.0
        };
        for i in -nx..=nx {
            let at = DVec2::new(i as f64 * pitch + shift, j as f64 * row);
            let d = if spread > 0.0 {
                d0 * (1.0 + spread * (2.0 * rng.random::<f64>() - 1.0))
            } else {
                d0
            };
            let r = 0.5 * d;
            let rho = at.length();
            if rho - r >= inner_edge && rho + r <= outer_edge {
                out.pos.push(centre + at);
                out.radius.push(r);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ring_is_dense_without_overlaps_and_inside_its_circles() {
        let (r_in, r_out, d0) = (2e-3, 3.2e-3, 60e-6);
        let c = DVec2::new(1e-3, 0.0);
        let ring = lattice_ring(c, r_in, r_out, d0, 0.03, 0.6, 7);
        let n = ring.pos.len();
        assert!(n > 500);
        let area: f64 = ring
            .radius
            .iter()
            .map(|r| std::f64::consts::PI * r * r)
            .sum();
        let phi = area / (std::f64::consts::PI * (r_out * r_out - r_in * r_in));
        assert!(phi > 0.78 && phi < 0.9, "phi {phi}");
        for i in 0..n {
            let rho = (ring.pos[i] - c).length();
            assert!(rho - ring.radius[i] >= r_in - 1e-12 && rho + ring.radius[i] <= r_out + 1e-12);
            for j in i + 1..n {
                let d = (ring.pos[j] - ring.pos[i]).length();
                assert!(
                    d >= ring.radius[i] + ring.radius[j] - 1e-12,
                    "overlap {i} {j}"
                );
            }
        }
    }
}
