//! Bonded interfaces that debond (Bardenhagen, Brackbill & Sulsky 1998). Bond strength is
//! carried by the points. At a node where two bodies' fields meet, the normal tension the
//! interface carries is compared with the node's bond:
//!
//! - tension ≤ bond: perfect bonding, every field takes the centre-of-mass velocity;
//! - tension > bond > 0: the bond fails at this node, and every point with weight at the
//!   node loses its bond, so the damage is remembered;
//! - bond = 0: Coulomb friction with μ when the fields approach or the stresses there
//!   press the interface (n·σ̄·n < 0, σ̄ the mass-weighted stress of every body at the
//!   node); free separation otherwise.
//!
//! The tension is the one the bond actually transmits: after integration, the stick
//! change of a body's momentum is the force the other side must exert to keep it
//! attached; summed with its neighbours' along the interface ([`smooth`]) and divided by
//! the interface length they stand for (|g_b − g_other| / (ρ_b + ρ_other), g the mass
//! gradients), it is a traction. Interpolated point stresses next to a stair-stepped
//! interface scatter by ±100 % of the traction (each cell mixes the two sides' thermal or
//! elastic strains), so a test on n·σ̄·n would fail the bond early and wherever the
//! lattice happens to put that noise: on the concentric cylinders at 50 × 50 cells it
//! failed at 0.7 of the static traction and the front crept with the loading (0.12 c_R);
//! with the smoothed force it fails at 0.99 and runs at 0.6 c_R.
//!
//! Two choices keep the algorithm's outcome a property of the interface, not of the
//! interpolation. The node's bond is the largest bond of the points that reach it, so a
//! neighbour's failure (which zeroes shared points) does not weaken a node that still
//! has intact material: failure spreads only by traction, i.e. by the stress waves the
//! opening sends along the interface. And a failure removes the whole bond of those
//! points: a partly bonded point would leave a residual strength that welds the
//! interface again once its tension has relaxed.

use crate::grid::Grid;
use crate::nodes::{Global, Patch};
use crate::particles::Particles;
use crate::setup::Setup;
use crate::shape::{Bspline2, Gimp, Kernel, Linear, ShapeFunction};
use crate::transfer::{Place, Stencil};
use glam::DVec2;
use rayon::prelude::*;

/// The bonded law at one interface node for one body: the momentum change (toward the
/// stick change `dp`, along the unit normal `n`) and whether the bond fails here now.
/// `pull` is the normal tension the bond must carry to keep the fields together (tested
/// against `strength`, the node's bond, when given); `traction` is the normal traction of
/// the stresses at the node, which decides, once debonded, whether the interface is in
/// compression.
#[inline]
pub fn bonded(
    dp: DVec2,
    n: DVec2,
    pull: Option<f64>,
    traction: f64,
    strength: f64,
    mu: f64,
) -> (Option<DVec2>, bool) {
    let failed = strength > 0.0 && pull.is_some_and(|p| p > strength);
    if strength > 0.0 && !failed {
        return (Some(dp), false);
    }
    let dn = dp.dot(n);
    if dn < 0.0 || traction < 0.0 {
        // Approaching, or pressed together: no relative normal motion either way, and
        // tangential slip resisted up to μ |Δp_n|.
        let t = dp - dn * n;
        let ts = t.length();
        let cap = mu * dn.abs();
        let dp = if ts > cap {
            dn * n + t * (cap / ts)
        } else {
            dp
        };
        (Some(dp), failed)
    } else {
        (None, failed)
    }
}

/// Width (cells) of the Gaussian exp(−(d/w)²) that smooths the bond's traction along the
/// interface. The nodal force over the nodal length scatters from −0.9 to 3.5 times the
/// static traction from node to node (the stair-stepped interface gives nodes very
/// different shares of it); smoothed over w = 1, 2, 3 cells it lies within 0.24 … 1.71,
/// 0.79 … 1.13 and 0.88 … 1.02 of it (concentric cylinders, 50 × 50 cells). Only with
/// the last does a failure's load make its neighbours fail in turn, so that the front
/// runs on its own (0.6 c_R) instead of creeping with the loading.
pub const SMOOTHING: f64 = 3.0;

/// The traction of every intact bond: Σ_j w_ij F_j / Σ_j w_ij L_j over the nodes j within
/// 2 [`SMOOTHING`] cells, with the forces F and lengths L of [`crate::contact::bond_forces`]
/// summed over bodies (`global.bond` must hold them; both are zero off the interface).
/// The Gaussian is a product of one-dimensional ones, so the sums are taken along the
/// rows first and then across the columns: 2 × 13 terms per node instead of 13².
pub fn smooth(global: &mut Global) {
    let [cols, rows] = global.dims;
    let wrap = global.wrap;
    let reach = (2.0 * SMOOTHING).ceil() as usize;
    let weights: Vec<f64> = (0..=reach)
        .map(|d| (-(d as f64 / SMOOTHING).powi(2)).exp())
        .collect();
    let bond = &global.bond;
    // Along y (rows): within each column, wrapping through the seam of a periodic y.
    let along: Vec<(f64, f64)> = (0..cols * rows)
        .into_par_iter()
        .map(|k| {
            let (c, r) = (k / rows, k % rows);
            let col = &bond[c * rows..][..rows];
            let (mut f, mut l) = (0.0, 0.0);
            let mut add = |rr: usize, d: usize| {
                let o = &col[rr];
                f += weights[d] * o.force;
                l += weights[d] * o.length;
            };
            match wrap {
                None => {
                    for rr in r.saturating_sub(reach)..(r + reach + 1).min(rows) {
                        add(rr, rr.abs_diff(r));
                    }
                }
                Some(w) if r >= crate::grid::GHOST && r < crate::grid::GHOST + w.ny => {
                    let reach = reach.min((w.ny - 1) / 2) as isize;
                    for d in -reach..=reach {
                        add(w.offset(r, d), d.unsigned_abs());
                    }
                }
                // Image rows hold nothing.
                Some(_) => {}
            }
            (f, l)
        })
        .collect();
    // Across x (columns), at the interface's nodes.
    let traction: Vec<f64> = (0..cols * rows)
        .into_par_iter()
        .map(|k| {
            if bond[k].length <= 0.0 {
                return 0.0;
            }
            let (c, r) = (k / rows, k % rows);
            let (mut f, mut l) = (0.0, 0.0);
            for cc in c.saturating_sub(reach)..(c + reach + 1).min(cols) {
                let (af, al) = along[cc * rows + r];
                let w = weights[cc.abs_diff(c)];
                f += w * af;
                l += w * al;
            }
            f / l
        })
        .collect();
    for (b, t) in global.bond.iter_mut().zip(traction) {
        b.traction = t;
    }
}

/// Every point of a strip with weight at a node where the bond failed loses its bond.
/// `cache` holds the strip's stencils (this step's), `patch` its body's nodes.
pub fn forget<K: Kernel>(bond: &mut [f64], cache: &[Stencil], patch: &Patch) {
    let rows = patch.size[1];
    for (b, s) in bond.iter_mut().zip(cache) {
        if *b == 0.0 {
            continue;
        }
        let first = (s.col - patch.lo[0]) * rows + (s.row - patch.lo[1]);
        'nodes: for x in 0..K::N {
            for y in 0..K::N {
                if s.wx[x] * s.wy[y] > 0.0 && patch.bond[first + x * rows + y].failed {
                    *b = 0.0;
                    break 'nodes;
                }
            }
        }
    }
}

/// Per body, the length of its surface and of the part that has debonded (m).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Lengths {
    /// Σ over nodes of |Σ_p V_p ∇S_ip|: the body's perimeter as the grid sees it
    /// (∫ |∇χ| dA of its smoothed indicator χ).
    pub surface: f64,
    /// The same sum with each node weighted by the mass-weighted damage 1 − bond/bond₀
    /// of the points there: the debonded stretch of its bonded interfaces.
    pub debonded: f64,
}

/// Surface and debonded lengths of every body (zeros for bodies without a bond).
/// `ranges[b]` is body b's point range (see [`crate::Solver::layout`]). A cold
/// diagnostic: one small grid per bonded body, built from the points.
pub fn lengths(setup: &Setup, p: &Particles, ranges: &[(usize, usize)]) -> Vec<Lengths> {
    match setup.shape {
        ShapeFunction::Linear => lengths_with::<Linear>(setup, p, ranges),
        ShapeFunction::Gimp => lengths_with::<Gimp>(setup, p, ranges),
        ShapeFunction::Bspline2 => lengths_with::<Bspline2>(setup, p, ranges),
    }
}

fn lengths_with<K: Kernel>(
    setup: &Setup,
    p: &Particles,
    ranges: &[(usize, usize)],
) -> Vec<Lengths> {
    (0..setup.bodies.len())
        .into_par_iter()
        .map(|b| {
            let bond0 = setup.contact.bond_of(b);
            let (start, end) = ranges[b];
            if bond0 <= 0.0 || start == end {
                return Lengths::default();
            }
            let damage = |i: usize| (1.0 - p.bond[i] / bond0).clamp(0.0, 1.0);
            body_lengths::<K>(&setup.grid, setup.half_width, p, start..end, damage)
        })
        .collect()
}

/// [`Lengths`] of the points `range` with per-point damage `damage`.
pub fn body_lengths<K: Kernel>(
    grid: &Grid,
    half_width: f64,
    p: &Particles,
    range: std::ops::Range<usize>,
    damage: impl Fn(usize) -> f64,
) -> Lengths {
    let place = Place {
        lo: grid.lo,
        inv_h: 1.0 / grid.h,
        lp: half_width,
        wrap_y: grid.period_y().map(|l| (grid.lo.y, l)),
    };
    let stencils: Vec<Stencil> = range
        .clone()
        .map(|i| place.stencil::<K>(p.pos[i]))
        .collect();
    let c0 = stencils.iter().map(|s| s.col).min().unwrap_or(0);
    let c1 = stencils.iter().map(|s| s.col + 3).max().unwrap_or(0);
    // Along a periodic y every row is its canonical one, so a body across the seam is
    // summed on one node there (its two halves are not two surfaces).
    let wrap = grid.canonical_rows();
    let (r0, rows) = match wrap {
        Some(_) => (0, grid.stored()[1]),
        None => {
            let r0 = stencils.iter().map(|s| s.row).min().unwrap_or(0);
            (
                r0,
                stencils.iter().map(|s| s.row + 3).max().unwrap_or(0) - r0,
            )
        }
    };
    let row = |r: usize| wrap.map_or(r, |w| w.canonical(r)) - r0;
    // Per node: mass, mass × damage, volume gradient.
    let mut nodes = vec![(0.0, 0.0, DVec2::ZERO); (c1 - c0) * rows];
    for (i, s) in range.zip(&stencils) {
        let (m, d, v) = (p.mass[i], damage(i), p.volume(i));
        for a in 0..K::N {
            for b in 0..K::N {
                let n = &mut nodes[(s.col + a - c0) * rows + row(s.row + b)];
                let w = s.wx[a] * s.wy[b];
                n.0 += w * m;
                n.1 += w * m * d;
                n.2 += v * DVec2::new(s.dx[a] * s.wy[b], s.wx[a] * s.dy[b]);
            }
        }
    }
    let mut out = Lengths::default();
    for (m, md, g) in nodes {
        if m > 0.0 {
            let len = g.length();
            out.surface += len;
            out.debonded += len * md / m;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Geometry;

    #[test]
    fn bond_logic_cases() {
        let n = DVec2::new(0.0, 1.0);
        let separating = DVec2::new(0.3, 0.5);
        let approaching = DVec2::new(0.3, -0.5);
        // Bonded: the whole stick change, in tension below the strength, in compression,
        // and in the passes that do not test the bond.
        for (pull, t) in [(Some(0.9), 0.5), (Some(-3.0), -2.0), (None, 5.0)] {
            assert_eq!(
                bonded(separating, n, pull, t, 1.0, 0.2),
                (Some(separating), false)
            );
        }
        // Failing: the tension exceeds the bond; separating fields are let go at once.
        assert_eq!(
            bonded(separating, n, Some(1.1), 0.5, 1.0, 0.2),
            (None, true)
        );
        // ... unless the stresses press the sides together: then Coulomb.
        let (dp, failed) = bonded(separating, n, Some(1.1), -0.5, 1.0, 0.2);
        assert!(failed && (dp.unwrap() - DVec2::new(0.1, 0.5)).length() < 1e-15);
        // Failed, in compression: held together and sliding with friction even if the
        // fields separate; sticking within the friction cone.
        let (dp, failed) = bonded(separating, n, Some(0.0), -0.5, 0.0, 0.2);
        assert!(!failed && (dp.unwrap() - DVec2::new(0.1, 0.5)).length() < 1e-15);
        let (dp, _) = bonded(separating, n, None, -0.5, 0.0, 1.0);
        assert_eq!(dp, Some(separating));
        // Failed, in tension or unloaded and separating: free.
        assert_eq!(
            bonded(separating, n, Some(2.0), 0.5, 0.0, 0.2),
            (None, false)
        );
        assert_eq!(bonded(separating, n, None, 0.0, 0.0, 0.2), (None, false));
        // Failed and approaching: Coulomb.
        let (dp, _) = bonded(approaching, n, Some(-1.0), 0.5, 0.0, 0.0);
        assert_eq!(dp, Some(DVec2::new(0.0, -0.5)));
    }

    #[test]
    fn smoothing_averages_force_over_length_of_intact_nodes() {
        let grid = Grid {
            lo: DVec2::ZERO,
            h: 1.0,
            cells: [20, 20],
            periodic_y: false,
        };
        let mut g = Global::new(&grid, true);
        // A row of intact nodes carrying 2 N per 0.5 m, one outlier, and a failed node
        // (no force, no length, as bond_forces leaves it) in the middle.
        for c in 3..15 {
            let k = g.index(c, 8);
            (g.bond[k].force, g.bond[k].length) = (2.0, 0.5);
        }
        let outlier = g.index(6, 8);
        g.bond[outlier].force = 6.0;
        let failed = g.index(10, 8);
        (g.bond[failed].force, g.bond[failed].length) = (0.0, 0.0);
        smooth(&mut g);
        assert_eq!(g.bond[failed].traction, 0.0);
        assert!((g.bond[g.index(13, 8)].traction - 4.0).abs() < 1e-3);
        let near = g.bond[g.index(6, 8)].traction;
        assert!(near > 4.0 && near < 6.0, "{near}");
        // Uniform force per length is left as it is.
        let far = g.bond[g.index(14, 8)].traction;
        assert!((far - 4.0).abs() < 1e-3, "{far}");
    }

    #[test]
    fn debonded_length_of_half_a_disk() {
        let grid = Grid {
            lo: DVec2::ZERO,
            h: 0.1,
            cells: [30, 30],
            periodic_y: false,
        };
        let (centre, radius) = (DVec2::splat(1.5), 1.0);
        let disk = Geometry::Disk {
            centre: centre.to_array(),
            radius,
        };
        let mut p = Particles::default();
        let pts = disk.fill(grid.lo, 0.05);
        let vol = disk.area() / pts.len() as f64;
        for x in pts {
            p.push(0, vol, vol, x, DVec2::ZERO);
        }
        let n = p.len();
        // Debond the upper half's rim: points within a cell of the surface with y > cy.
        let rim = |i: usize| {
            let d = p.pos[i] - centre;
            d.y > 0.0 && d.length() > radius - 0.15
        };
        for shape in [
            ShapeFunction::Linear,
            ShapeFunction::Gimp,
            ShapeFunction::Bspline2,
        ] {
            let l = match shape {
                ShapeFunction::Linear => {
                    body_lengths::<Linear>(&grid, 0.25, &p, 0..n, |i| rim(i) as u8 as f64)
                }
                ShapeFunction::Gimp => {
                    body_lengths::<Gimp>(&grid, 0.25, &p, 0..n, |i| rim(i) as u8 as f64)
                }
                ShapeFunction::Bspline2 => {
                    body_lengths::<Bspline2>(&grid, 0.25, &p, 0..n, |i| rim(i) as u8 as f64)
                }
            };
            let perimeter = std::f64::consts::TAU * radius;
            assert!(
                (l.surface / perimeter - 1.0).abs() < 0.02,
                "{shape:?}: {l:?}"
            );
            assert!(
                (l.debonded / (0.5 * perimeter) - 1.0).abs() < 0.03,
                "{shape:?}: {l:?}"
            );
        }
    }
}
