//! Packing fraction of a sub-region: the area of the disks inside it over its area.

use crate::region::Region;
use glam::DVec2;
use rayon::prelude::*;

/// Radial × angular quadrature points for disks cut by the region's boundary.
const RINGS: usize = 12;
const SECTORS: usize = 48;

/// Area of the disk (`c`, `r`) inside `region`: exact for disks wholly in or out,
/// midpoint quadrature in polar cells (12 × 48) for the few the boundary cuts.
pub fn disk_area_inside(region: &Region, c: DVec2, r: f64) -> f64 {
    let d = region.boundary_distance(c);
    let full = std::f64::consts::PI * r * r;
    if d >= r {
        return full;
    }
    if d <= -r {
        return 0.0;
    }
    let mut inside = 0.0;
    for a in 0..RINGS {
        // Equal-area rings: radius of the ring's area midpoint.
        let rho = r * ((a as f64 + 0.5) / RINGS as f64).sqrt();
        for b in 0..SECTORS {
            let t = std::f64::consts::TAU * (b as f64 + 0.5) / SECTORS as f64;
            if region.boundary_distance(c + rho * DVec2::from_angle(t)) >= 0.0 {
                inside += 1.0;
            }
        }
    }
    full * inside / (RINGS * SECTORS) as f64
}

/// Packing fraction of `region` (disk area inside it over its area). In a periodic
/// x direction the disks are used as given: callers wrap positions into the period.
pub fn packing_fraction(pos: &[DVec2], radius: &[f64], region: &Region) -> f64 {
    let covered: f64 = pos
        .par_iter()
        .zip(radius.par_iter())
        .with_min_len(4096)
        .map(|(c, r)| disk_area_inside(region, *c, *r))
        .collect::<Vec<f64>>()
        .iter()
        .sum();
    covered / region.area()
}

/// Packing fraction of the bulk: the points at least `margin` from every boundary
/// of `region`. NaN when the margin leaves nothing.
pub fn bulk_fraction(pos: &[DVec2], radius: &[f64], region: &Region, margin: f64) -> f64 {
    match region.shrink(margin) {
        Some(bulk) => packing_fraction(pos, radius, &bulk),
        None => f64::NAN,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cut_disk_area() {
        let r = Region::Rectangle {
            lo: DVec2::ZERO,
            hi: DVec2::new(10.0, 10.0),
            periodic_x: false,
        };
        let half = disk_area_inside(&r, DVec2::new(0.0, 5.0), 1.0);
        assert!((half - std::f64::consts::FRAC_PI_2).abs() < 0.01, "{half}");
        assert_eq!(
            disk_area_inside(&r, DVec2::new(5.0, 5.0), 1.0),
            std::f64::consts::PI
        );
        assert_eq!(disk_area_inside(&r, DVec2::new(-5.0, 5.0), 1.0), 0.0);
    }

    #[test]
    fn square_lattice_fraction() {
        // Unit disks on a pitch-2 square lattice cover π/4 of any large box.
        let mut pos = Vec::new();
        for i in -5..15 {
            for j in -5..15 {
                pos.push(DVec2::new(2.0 * i as f64 + 1.0, 2.0 * j as f64 + 1.0));
            }
        }
        let rad = vec![1.0; pos.len()];
        let region = Region::Rectangle {
            lo: DVec2::ZERO,
            hi: DVec2::new(20.0, 20.0),
            periodic_x: false,
        };
        let phi = bulk_fraction(&pos, &rad, &region, 3.0);
        assert!((phi - std::f64::consts::FRAC_PI_4).abs() < 2e-3, "{phi}");
    }
}
