//! Shape functions: linear ("classic" MPM), uGIMP and quadratic B-splines, as tensor
//! products of 1D weights. Every kernel fills a 3-node stencil per axis (linear leaves the
//! third weight zero), so transfer loops are the same code for all three and the compiler
//! unrolls them for each `Kernel`.

use serde::{Deserialize, Serialize};

/// ⌊x⌋ for 0 ≤ x < 2³¹ by truncation, as (integer, float): `f64::floor` is a libm call
/// on baseline x86-64, and the saturating `as u64` costs a sign fix-up each way, while
/// `as i32` is one instruction. Stencil positions are never negative (one ghost layer
/// in front of the domain).
#[inline(always)]
pub fn floor_pos(x: f64) -> (usize, f64) {
    let i = x as i32;
    (i as usize, i as f64)
}

/// Which shape function the grid uses (chosen in the scenario).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ShapeFunction {
    /// Bilinear hat functions: C⁰ weights, gradients jump at cell faces.
    Linear,
    /// Uniform GIMP (Bardenhagen & Kober 2004): the hat convolved with the particle's
    /// square domain of half-width `lp`; C¹ weights, continuous gradients.
    Gimp,
    /// Quadratic B-spline (support 3 cells).
    Bspline2,
}

impl ShapeFunction {
    /// The names accepted in a scenario.
    pub const NAMES: &'static str = "\"linear\", \"gimp\" or \"bspline2\"";
}

/// 1D weights and their derivatives (per cell size, i.e. in grid units) at the three
/// nodes `base, base + 1, base + 2`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Axis {
    /// Stored index of the first node (ghost offset included).
    pub base: usize,
    /// Weights.
    pub w: [f64; 3],
    /// d(weight)/d(particle position) × h.
    pub dw: [f64; 3],
}

/// A shape function evaluated along one axis. `xi` is the particle position in grid units
/// measured from the first *stored* node (so it is ≥ 1 inside the domain); `lp` is the
/// GIMP half-width in grid units.
pub trait Kernel: Send + Sync {
    /// Nodes per axis that can carry a non-zero weight.
    const N: usize;
    /// Weights along one axis.
    fn axis(xi: f64, lp: f64) -> Axis;
}

/// Bilinear hat functions.
pub struct Linear;
/// uGIMP.
pub struct Gimp;
/// Quadratic B-spline.
pub struct Bspline2;

impl Kernel for Linear {
    const N: usize = 2;
    #[inline(always)]
    fn axis(xi: f64, _lp: f64) -> Axis {
        let (ci, c) = floor_pos(xi);
        let f = xi - c;
        Axis {
            base: ci,
            w: [1.0 - f, f, 0.0],
            dw: [-1.0, 1.0, 0.0],
        }
    }
}

/// uGIMP weight and derivative of a node at signed distance `r` (particle − node, grid
/// units) for a particle of half-width `lp` ≤ ½.
#[inline(always)]
fn gimp_1d(r: f64, lp: f64) -> (f64, f64) {
    let a = r.abs();
    let s = if r < 0.0 { -1.0 } else { 1.0 };
    if a < lp {
        (1.0 - (r * r + lp * lp) / (2.0 * lp), -r / lp)
    } else if a <= 1.0 - lp {
        (1.0 - a, -s)
    } else if a < 1.0 + lp {
        let q = 1.0 + lp - a;
        (q * q / (4.0 * lp), -s * q / (2.0 * lp))
    } else {
        (0.0, 0.0)
    }
}

impl Kernel for Gimp {
    const N: usize = 3;
    #[inline(always)]
    fn axis(xi: f64, lp: f64) -> Axis {
        let (ci, c) = floor_pos(xi);
        // A particle within lp of its cell's left node still overlaps the cell before.
        let back = xi - c < lp;
        let base = if back { c - 1.0 } else { c };
        let mut out = Axis {
            base: ci - back as usize,
            ..Axis::default()
        };
        for k in 0..3 {
            let (w, dw) = gimp_1d(xi - (base + k as f64), lp);
            out.w[k] = w;
            out.dw[k] = dw;
        }
        out
    }
}

impl Kernel for Bspline2 {
    const N: usize = 3;
    #[inline(always)]
    fn axis(xi: f64, _lp: f64) -> Axis {
        let (bi, base) = floor_pos(xi - 0.5);
        let f = xi - base;
        Axis {
            base: bi,
            w: [
                0.5 * (1.5 - f) * (1.5 - f),
                0.75 - (f - 1.0) * (f - 1.0),
                0.5 * (f - 0.5) * (f - 0.5),
            ],
            dw: [f - 1.5, 2.0 * (1.0 - f), f - 0.5],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_kernel<K: Kernel>(lp: f64) {
        // Partition of unity, zero-sum gradients, and gradients that match finite
        // differences of the weights, at many positions.
        for k in 0..997 {
            let xi = 2.0 + 3.0 * k as f64 / 997.0 + 1e-7;
            let a = K::axis(xi, lp);
            let sum: f64 = a.w.iter().sum();
            let dsum: f64 = a.dw.iter().sum();
            assert!((sum - 1.0).abs() < 1e-12, "sum {sum} at {xi}");
            assert!(dsum.abs() < 1e-12, "dsum {dsum} at {xi}");
            let first: f64 = (0..3).map(|n| a.w[n] * (a.base + n) as f64).sum();
            assert!((first - xi).abs() < 1e-12, "linear reproduction at {xi}");
            let e = 1e-6;
            let (p, m) = (K::axis(xi + e, lp), K::axis(xi - e, lp));
            if p.base == a.base && m.base == a.base {
                for n in 0..3 {
                    let fd = (p.w[n] - m.w[n]) / (2.0 * e);
                    assert!(
                        (fd - a.dw[n]).abs() < 1e-5,
                        "node {n} at {xi}: {fd} vs {}",
                        a.dw[n]
                    );
                }
            }
        }
    }

    #[test]
    fn kernels_are_consistent() {
        check_kernel::<Linear>(0.25);
        check_kernel::<Gimp>(0.25);
        check_kernel::<Gimp>(0.125);
        check_kernel::<Gimp>(0.5);
        check_kernel::<Bspline2>(0.25);
    }

    #[test]
    fn gimp_is_continuous_across_stencil_shifts() {
        // The weight of one node seen from either side of a base change must agree.
        let lp = 0.25;
        for xi in [3.25, 4.25, 5.25] {
            let (a, b) = (Gimp::axis(xi - 1e-9, lp), Gimp::axis(xi + 1e-9, lp));
            for node in 2..7usize {
                let wa = (0..3).find(|&n| a.base + n == node).map_or(0.0, |n| a.w[n]);
                let wb = (0..3).find(|&n| b.base + n == node).map_or(0.0, |n| b.w[n]);
                assert!((wa - wb).abs() < 1e-8, "node {node} at {xi}: {wa} vs {wb}");
            }
        }
    }
}
