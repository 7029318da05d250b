//! The velocity gradient ∇v of the coarse-grained field (xue-2019 Eq. 5), by finite
//! differences between neighbouring bins.
//!
//! Each bin's velocity is taken to sit at its mass centroid. ∇v of bin `k` is the
//! least-squares fit of `v_n − v_k = L (x_n − x_k)` over its four neighbours (the rings
//! in and out, the sectors on either side, sectors wrapping around), which on a regular
//! grid is the central difference — one-sided where a neighbour is empty. When the four
//! do not span both directions (a bin at a corner of the occupied region), the four
//! diagonal neighbours are added; if the fit is still degenerate ∇v is NaN.
//!
//! Because the positions are the centroids rather than the bin centres, the fit is exact
//! for any linear velocity field (uniform expansion, rigid rotation, simple shear)
//! whatever the grains' arrangement in the bins — the property the unit tests check.

use super::polar::PolarGrid;
use glam::{DMat2, DVec2};
use rayon::prelude::*;

/// Relative size below which the normal matrix Σ dx⊗dx counts as singular.
const SINGULAR: f64 = 1e-6;

/// ∇v (`L[a][b] = ∂v_a/∂x_b`, so `L · dx = dv`) for every bin; NaN where the bin is
/// empty or its neighbours do not determine it. `valid[k]` says whether bin `k` has a
/// velocity; `position` and `velocity` are per bin.
pub fn velocity_gradient(
    grid: &PolarGrid,
    position: &[DVec2],
    velocity: &[DVec2],
    valid: &[bool],
) -> Vec<DMat2> {
    let nan = DMat2::from_cols(DVec2::NAN, DVec2::NAN);
    let (nr, nt) = (grid.n_r() as i64, grid.n_theta() as i64);
    let at = |i: i64, j: i64| -> Option<usize> {
        if i < 0 || i >= nr {
            return None;
        }
        let k = grid.index(i as usize, j.rem_euclid(nt) as usize);
        valid[k].then_some(k)
    };
    (0..grid.len())
        .into_par_iter()
        .map(|k| {
            if !valid[k] {
                return nan;
            }
            let (i, j) = grid.ring_sector(k);
            let (i, j) = (i as i64, j as i64);
            let mut fit = Fit::default();
            for (di, dj) in [(-1, 0), (1, 0), (0, -1), (0, 1)] {
                if let Some(n) = at(i + di, j + dj) {
                    fit.add(position[n] - position[k], velocity[n] - velocity[k]);
                }
            }
            if fit.singular() {
                for (di, dj) in [(-1, -1), (-1, 1), (1, -1), (1, 1)] {
                    if let Some(n) = at(i + di, j + dj) {
                        fit.add(position[n] - position[k], velocity[n] - velocity[k]);
                    }
                }
            }
            if fit.singular() {
                nan
            } else {
                fit.solve()
            }
        })
        .collect()
}

/// Normal equations of the least-squares fit `dv ≈ L dx`: L = (Σ dv⊗dx)(Σ dx⊗dx)⁻¹.
struct Fit {
    xx: DMat2,
    vx: DMat2,
}

impl Default for Fit {
    // Not derived: `DMat2::default()` is the identity.
    fn default() -> Self {
        Fit {
            xx: DMat2::ZERO,
            vx: DMat2::ZERO,
        }
    }
}

impl Fit {
    fn add(&mut self, dx: DVec2, dv: DVec2) {
        self.xx += outer(dx, dx);
        self.vx += outer(dv, dx);
    }

    fn singular(&self) -> bool {
        let tr = self.xx.x_axis.x + self.xx.y_axis.y;
        // NaN positions make the determinant NaN: singular too.
        self.xx.determinant().is_nan() || self.xx.determinant() <= SINGULAR * tr * tr
    }

    fn solve(&self) -> DMat2 {
        self.vx * self.xx.inverse()
    }
}

/// The dyad `a ⊗ b` (`[a_i b_j]`).
#[inline]
pub(crate) fn outer(a: DVec2, b: DVec2) -> DMat2 {
    DMat2::from_cols(a * b.x, a * b.y)
}

/// The parts of a velocity gradient the paper reports (Eqs. 5, 7, 8).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rates {
    /// Dilation rate D = ½ tr G = ½ div v (1/s).
    pub dilation: f64,
    /// Shear rate γ̇ = (½ tr G_d²)^½ (1/s).
    pub shear_rate: f64,
    /// Vorticity ∂v_y/∂x − ∂v_x/∂y (1/s).
    pub vorticity: f64,
}

/// Splits `L = ∇v` into the dilation rate, shear rate and vorticity, with
/// G = ½(L + Lᵀ) = D·I + G_d (Eqs. 5, 7) and γ̇ from Eq. 8.
pub fn rates(l: DMat2) -> Rates {
    let (gxx, gyy) = (l.x_axis.x, l.y_axis.y);
    let gxy = 0.5 * (l.y_axis.x + l.x_axis.y);
    // G_d = [[a, b], [b, −a]] with a = (gxx − gyy)/2: ½ tr G_d² = a² + b².
    let a = 0.5 * (gxx - gyy);
    Rates {
        dilation: 0.5 * (gxx + gyy),
        shear_rate: (a * a + gxy * gxy).sqrt(),
        vorticity: l.x_axis.y - l.y_axis.x,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rates_of_simple_fields() {
        // Uniform expansion v = a x.
        let r = rates(DMat2::from_diagonal(DVec2::splat(3.0)));
        assert_eq!((r.dilation, r.shear_rate, r.vorticity), (3.0, 0.0, 0.0));
        // Rigid rotation v = ω ẑ × x: L = [[0, −ω], [ω, 0]].
        let w = 2.0;
        let r = rates(DMat2::from_cols(DVec2::new(0.0, w), DVec2::new(-w, 0.0)));
        assert_eq!((r.dilation, r.shear_rate, r.vorticity), (0.0, 0.0, 2.0 * w));
        // Simple shear v_x = k y: G_d has b = k/2, so γ̇ = k/2 (Eq. 8).
        let k = 4.0;
        let r = rates(DMat2::from_cols(DVec2::ZERO, DVec2::new(k, 0.0)));
        assert_eq!((r.dilation, r.shear_rate, r.vorticity), (0.0, 2.0, -4.0));
        // Eq. 8 literally: γ̇² = ½ tr(G_d²).
        let l = DMat2::from_cols(DVec2::new(1.0, 0.3), DVec2::new(-0.7, 2.0));
        let g = 0.5 * (l + l.transpose());
        let d = 0.5 * (g.x_axis.x + g.y_axis.y);
        let gd = g - DMat2::from_diagonal(DVec2::splat(d));
        let gd2 = gd * gd;
        let expect = (0.5 * (gd2.x_axis.x + gd2.y_axis.y)).sqrt();
        assert!((rates(l).shear_rate - expect).abs() < 1e-15);
    }

    #[test]
    fn fit_is_exact_for_a_linear_field_on_scattered_points() {
        let l = DMat2::from_cols(DVec2::new(1.5, -0.2), DVec2::new(0.4, -0.9));
        let mut f = Fit::default();
        for k in 0..3 {
            let dx = DVec2::new(0.3 + k as f64, 1.0 - 0.7 * k as f64);
            f.add(dx, l * dx);
        }
        assert!(!f.singular());
        let got = f.solve();
        assert!((got - l).abs().to_cols_array().iter().all(|e| *e < 1e-12));
        let mut line = Fit::default();
        line.add(DVec2::X, DVec2::Y);
        line.add(-DVec2::X, DVec2::Y);
        assert!(line.singular());
    }
}
