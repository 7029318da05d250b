//! Where a spread deposit of spheres ends: the edge of its continuous part, read from
//! how much of the floor the grains cover, ring by ring about an axis.
//!
//! One reading of Lube et al.'s (J. Fluid Mech. 508, 2004) run-out, the front of the
//! continuous deposit (their own wording was not at hand: VALIDATION.md), reported as a
//! figure beside the collapse's check, which keeps the 99 % radius; grains that
//! rolled away alone lie on bare floor beyond it and are not the deposit, however far
//! they went. Here the floor is cut into rings one mean grain diameter wide; a ring's
//! coverage is the grains' projected area within it over its area (above 1 where grains
//! stack). Going out from the axis, the deposit ends where the coverage first falls
//! below [`COVERED`], the level half-way between bare floor and floor under grains (the
//! edge a picture of the deposit shows at half contrast, and about where hard discs on a
//! plane can first form a connected layer: their random sequential packing jams at
//! 0.547). The crossing is interpolated between ring centres.

/// The coverage (grain projected area over floor area, azimuthally averaged) below
/// which the floor counts as bare: half of it under grains.
pub const COVERED: f64 = 0.5;

/// The area of a disc of radius `r` between the lines at offsets `x0` ≤ `x1` from its
/// centre (the offsets clamped to the disc).
fn strip(r: f64, x0: f64, x1: f64) -> f64 {
    let g = |x: f64| {
        let x = x.clamp(-r, r);
        x * (r * r - x * x).max(0.0).sqrt() + r * r * (x / r).asin()
    };
    g(x1) - g(x0)
}

/// The coverage of rings `width` wide about the axis by spheres at distances `s` from it
/// with radii `r`: ring k spans [k·width, (k+1)·width). The last ring is bare.
///
/// Each sphere's shadow is cut into the rings by straight lines across it, which is
/// exact as the ring's radius grows beside the sphere's and errs only at the axis, far
/// from the edge sought; a shadow reaching across the axis is counted in ring 0.
pub fn coverage(s: &[f64], r: &[f64], width: f64) -> Vec<f64> {
    let outer = s.iter().zip(r).map(|(s, r)| s + r).fold(0.0, f64::max);
    let rings = (outer / width).floor() as usize + 2;
    let mut area = vec![0.0; rings];
    for (&s, &r) in s.iter().zip(r) {
        let first = ((s - r).max(0.0) / width).floor() as usize;
        let last = ((s + r) / width).floor() as usize;
        for (k, a) in area.iter_mut().enumerate().take(last + 1).skip(first) {
            // Ring 0 also takes what lies beyond the axis.
            let lo = if k == 0 { -r } else { k as f64 * width - s };
            *a += strip(r, lo, (k + 1) as f64 * width - s);
        }
    }
    area.iter()
        .enumerate()
        .map(|(k, a)| a / (std::f64::consts::PI * (2 * k + 1) as f64 * width * width))
        .collect()
}

/// The radius where the continuous deposit ends, from the rings' `coverage` (`width`
/// wide): the first fall below [`COVERED`] going out from the axis, interpolated between
/// the ring centres either side (0 when the first ring is already bare).
pub fn edge(coverage: &[f64], width: f64) -> f64 {
    let Some(k) = coverage.iter().position(|&c| c < COVERED) else {
        return coverage.len() as f64 * width;
    };
    if k == 0 {
        return 0.0;
    }
    let (inner, outer) = (coverage[k - 1], coverage[k]);
    (k as f64 - 0.5 + (inner - COVERED) / (inner - outer)) * width
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn a_strip_across_the_whole_disc_is_the_disc() {
        assert!((strip(2.0, -5.0, 5.0) - 4.0 * PI).abs() < 1e-12);
        assert!((strip(2.0, 0.0, 2.0) - 2.0 * PI).abs() < 1e-12);
    }

    #[test]
    fn every_grain_shadow_is_counted_once() {
        // Spheres anywhere, some across ring boundaries and one across the axis.
        let s = [0.3, 1.0, 2.5, 7.9, 12.0];
        let r = [0.5, 0.4, 0.5, 0.45, 0.5];
        let c = coverage(&s, &r, 1.0);
        let total: f64 = c
            .iter()
            .enumerate()
            .map(|(k, c)| c * PI * (2 * k + 1) as f64)
            .sum();
        let shadows: f64 = r.iter().map(|r| PI * r * r).sum();
        assert!((total - shadows).abs() < 1e-12, "{total} {shadows}");
        assert_eq!(*c.last().unwrap(), 0.0);
    }

    #[test]
    fn a_covered_disc_ends_at_its_rim_and_strays_do_not_count() {
        // Coverage 1 out to 10 rings, then 0.2 (grains rolled off alone), then bare:
        // the edge is half-way from the last covered centre to the first sparse one,
        // scaled by how far 1 → 0.2 crosses 0.5.
        let mut c = vec![1.0; 10];
        c.extend([0.2, 0.2, 0.0]);
        let e = edge(&c, 2.0);
        assert!((e - (9.5 + 0.5 / 0.8) * 2.0).abs() < 1e-12, "{e}");
        assert_eq!(edge(&[0.1, 1.0], 2.0), 0.0);
    }

    #[test]
    fn a_packed_monolayer_disc_has_its_edge_at_its_rim() {
        // Discs of radius 1 on a triangular lattice (coverage 0.907) out to radius 40.
        let (mut s, mut r) = (Vec::new(), Vec::new());
        for i in -50..=50 {
            for j in -50..=50 {
                let (x, y) = (2.0 * i as f64 + j as f64, 3f64.sqrt() * j as f64);
                if x.hypot(y) <= 40.0 {
                    s.push(x.hypot(y));
                    r.push(1.0);
                }
            }
        }
        let e = edge(&coverage(&s, &r, 2.0), 2.0);
        assert!((e - 41.0).abs() < 2.0, "{e}");
    }
}
