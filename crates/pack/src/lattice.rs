//! The templated start: bulk disks on the sites of one triangular lattice (rows along
//! x) covering the whole region, so the packing starts with a single crystal
//! orientation. Random nucleation in a fluid gives grains of random orientation whose
//! ψ6 phases cancel; a template is the only way the whole annulus can share one.
//! Whether the order survives is then up to the size distribution and the growth:
//! a narrow distribution keeps it, a broad one cannot hold a crystal and disorders.

use crate::sizes::Distribution;
use crate::spec::{FinishSpec, ProtocolSpec};
use glam::DVec2;
use grains_analysis::fraction::bulk_fraction;
use grains_analysis::grid::CellGrid;
use grains_analysis::region::Region;
use grains_analysis::INTERIOR_MARGIN_D0;
use grains_core::rng;
use rand::RngExt;

/// Packing fraction of the lattice start at the drawn sizes when the growth goes on to
/// jamming: sets how many disks the region holds. Growth from the lattice jams near it,
/// so a packing grown to jamming ends with a realised d0 within about 1 % of the nominal
/// one. A growth that ends at a target fraction fills the plane at that target instead
/// ([`lattice_fill`]), for the same reason.
pub const LATTICE_FILL: f64 = 0.89;

/// The fraction the lattice start fills at the drawn sizes: the target fraction when
/// the growth ends there (`finish = "target"`), else [`LATTICE_FILL`]. Either way the
/// disks end near their drawn sizes, so the realised d0 is the nominal one (with the
/// jamming fill, a packing stopped at 0.84 ended 2.7 % under it).
pub fn lattice_fill(p: &ProtocolSpec) -> f64 {
    match p.finish {
        FinishSpec::Target => p.target_fraction,
        FinishSpec::Jammed => LATTICE_FILL,
    }
}

/// The lattice start before any relaxation, in units of the nominal d0: the lining,
/// then one bulk disk on every site with its drawn radius (scale 1, where the bulk
/// disks fill `fill` of the plane, see [`lattice_fill`]; large neighbours may overlap).
#[derive(Clone, Debug)]
pub struct Template {
    /// Centres: the lining's, then the sites'.
    pub pos: Vec<DVec2>,
    /// Radii at the drawn sizes.
    pub radius: Vec<f64>,
    /// Leading lining disks.
    pub fixed: usize,
    /// Bulk packing fraction of the bulk disks at the drawn sizes.
    pub fraction: f64,
    /// Nearest-neighbour spacing of the sites.
    pub spacing: f64,
}

/// The lattice start of `region` (d0 units) lined by `lining`, sizes drawn from
/// `sizes` (SI, divided by `d0`) with `size_rng`, lattice placed by the seed's stream,
/// spaced so that the drawn sizes fill `fill` of the plane.
pub fn template(
    region: &Region,
    lining: &[(DVec2, f64)],
    sizes: &Distribution,
    d0: f64,
    fill: f64,
    seed: u64,
    size_rng: &mut rng::Rng,
) -> Template {
    let mut place = rng::stream(seed, 2);
    let shift = DVec2::new(place.random::<f64>(), place.random::<f64>());
    let msq = sizes.mean_square() / (d0 * d0);
    let a = (std::f64::consts::FRAC_PI_4 * msq / (fill * 0.75f64.sqrt())).sqrt();
    let r_lining = lining.iter().map(|l| l.1).fold(0.0, f64::max);
    let sites = sites(region, a, 2.0 * r_lining + 0.5 * a, shift);
    let fixed = lining.len();
    let mut pos: Vec<DVec2> = lining.iter().map(|l| l.0).collect();
    let mut radius: Vec<f64> = lining.iter().map(|l| l.1).collect();
    pos.extend_from_slice(&sites);
    radius.extend(sites.iter().map(|_| 0.5 * sizes.sample(size_rng) / d0));
    let fraction = bulk_fraction(&pos[fixed..], &radius[fixed..], region, INTERIOR_MARGIN_D0);
    Template {
        pos,
        radius,
        fixed,
        fraction,
        spacing: a,
    }
}

/// Triangular-lattice sites of nearest-neighbour spacing `a` inside `region`, each at
/// least `clear` from every wall, in row order. `shift` (fractions of a spacing, in
/// [0, 1)²) places the lattice; in periodic x the spacing along x is adjusted to a
/// whole number of sites per period.
pub fn sites(region: &Region, a: f64, clear: f64, shift: DVec2) -> Vec<DVec2> {
    let (lo, hi) = region.bounds();
    let h = a * 3f64.sqrt() / 2.0;
    let ax = match region.period_x() {
        Some(l) => l / ((l / a).round().max(1.0)),
        None => a,
    };
    let rows = ((hi.y - lo.y) / h).ceil() as i64 + 1;
    let cols = ((hi.x - lo.x) / ax).ceil() as i64 + 1;
    let mut out = Vec::new();
    for j in 0..rows {
        let y = lo.y + (shift.y + j as f64) * h;
        let odd = if j % 2 == 1 { 0.5 } else { 0.0 };
        for i in 0..cols {
            let x = lo.x + (shift.x + odd + i as f64) * ax;
            let q = DVec2::new(x, y);
            let inside_period = region.period_x().is_none_or(|l| x < lo.x + l);
            if inside_period && region.boundary_distance(q) >= clear {
                out.push(q);
            }
        }
    }
    out
}

/// The largest factor by which the radii of the disks from `fixed` on can be multiplied
/// with no disk overlapping another or a wall (1 or more when nothing touches).
pub fn clearance_factor(region: &Region, pos: &[DVec2], rad: &[f64], fixed: usize) -> f64 {
    let r_max = rad.iter().cloned().fold(0.0, f64::max);
    let (mut lo, mut hi) = region.bounds();
    for p in pos {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let grid = CellGrid::build(pos, lo, hi, 2.0 * r_max, region.period_x());
    let mut f = f64::INFINITY;
    for i in fixed..pos.len() {
        f = f.min(region.boundary_distance(pos[i]) / rad[i]);
        grid.for_each_near(pos[i], 1, |j| {
            let j = j as usize;
            if j == i {
                return;
            }
            let d = region.delta(pos[i], pos[j]).length();
            // A mobile pair grows together; a fixed partner keeps its radius.
            let g = if j < fixed {
                (d - rad[j]) / rad[i]
            } else {
                d / (rad[i] + rad[j])
            };
            f = f.min(g);
        });
    }
    f
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sites_form_a_triangular_lattice_inside_the_region() {
        let region = Region::Annulus {
            centre: DVec2::ZERO,
            r_in: 10.0,
            r_out: 20.0,
        };
        let s = sites(&region, 1.0, 0.5, DVec2::new(0.3, 0.7));
        // Number density 2/√3 over the area left by the clearance.
        let area = std::f64::consts::PI * (19.5f64.powi(2) - 10.5f64.powi(2));
        let expect = area * 2.0 / 3f64.sqrt();
        assert!((s.len() as f64 / expect - 1.0).abs() < 0.02, "{}", s.len());
        assert!(s.iter().all(|q| region.boundary_distance(*q) >= 0.5));
        // Every site's nearest neighbour is one spacing away.
        let r = vec![0.5; s.len()];
        let f = clearance_factor(&region, &s, &r, 0);
        assert!((f - 1.0).abs() < 1e-9, "{f}");
    }

    #[test]
    fn periodic_rows_close_on_themselves() {
        let region = Region::Rectangle {
            lo: DVec2::ZERO,
            hi: DVec2::new(10.3, 6.0),
            periodic_x: true,
        };
        let s = sites(&region, 1.0, 0.5, DVec2::ZERO);
        let r = vec![0.5; s.len()];
        let f = clearance_factor(&region, &s, &r, 0);
        // Ten sites per row, 1.03 apart along x (across the seam too); rows √3/2 apart.
        let diagonal = (0.515f64 * 0.515 + 0.75).sqrt();
        assert!((f - diagonal).abs() < 1e-9, "{f}");
        assert_eq!(s.iter().filter(|q| q.y < 1.0).count() % 10, 0);
    }
}
