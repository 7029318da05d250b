//! The closed-form answers the MPM checks compare with: plane-strain elastic constants,
//! the J2 shear plateau and hardening slope, the free thermal strain, the static
//! solution of two bonded concentric cylinders with thermal strains (physics.md §3.2),
//! the plane-strain Rayleigh speed, and least-squares fits.

/// Poisson's ratio ν = (3K − 2G)/(2(3K + G)).
pub fn poisson(bulk: f64, shear: f64) -> f64 {
    (3.0 * bulk - 2.0 * shear) / (2.0 * (3.0 * bulk + shear))
}

/// Young's modulus E = 9KG/(3K + G).
pub fn young(bulk: f64, shear: f64) -> f64 {
    9.0 * bulk * shear / (3.0 * bulk + shear)
}

/// In-plane strain of a free body in plane strain for a thermal strain α ΔT: the
/// confined z direction pushes the plane out by (1 + ν) α ΔT (α ΔT is the free strain
/// in 3D or in plane stress).
pub fn plane_strain_thermal(bulk: f64, shear: f64, alpha_dt: f64) -> f64 {
    (1.0 + poisson(bulk, shear)) * alpha_dt
}

/// Yield stress in shear of a von Mises material, k = σ_y/√3.
pub fn shear_yield(yield_stress: f64) -> f64 {
    yield_stress / 3f64.sqrt()
}

/// dτ/dγ of a J2 material with linear isotropic hardening H in simple shear once it
/// yields: G H/(H + 3G).
pub fn hardening_slope(shear: f64, hardening: f64) -> f64 {
    shear * hardening / (hardening + 3.0 * shear)
}

/// One elastic cylinder or ring in plane strain: (K, G) and its free thermal strain
/// α ΔT.
#[derive(Clone, Copy, Debug)]
pub struct Layer {
    /// Bulk modulus (Pa).
    pub bulk: f64,
    /// Shear modulus (Pa).
    pub shear: f64,
    /// α ΔT.
    pub alpha_dt: f64,
}

impl Layer {
    /// λ + G = K + G/3, the plane-strain modulus of an equibiaxial in-plane stress
    /// (σ_rr = σ_θθ = s gives ε = s/(2(λ + G))).
    fn biaxial(&self) -> f64 {
        self.bulk + self.shear / 3.0
    }
}

/// Radial stress σ_rr(a) at the interface of a disk of radius `a` (`inner`) bonded to a
/// ring a < r < b (`outer`), both free of load, after thermal strains, in plane strain.
/// The disk is under uniform σ_rr = σ_θθ = −p; the ring follows Lamé's solution with
/// inner pressure p; matching the radial displacements at r = a gives
/// p = (ε_in − ε_out) / [1/(2L₁) + (a²/(2L₂) + b²/(2G₂))/(b² − a²)], L = K + G/3 and
/// ε = (1 + ν) α ΔT each layer's plane-strain free strain. For equal moduli this is
/// physics.md §3.2's σ_rr(a) = −2 L G ε_T (1 − a²/b²)/(L + G).
pub fn concentric_interface_stress(a: f64, b: f64, inner: Layer, outer: Layer) -> f64 {
    let free = |l: &Layer| plane_strain_thermal(l.bulk, l.shear, l.alpha_dt);
    let compliance = 1.0 / (2.0 * inner.biaxial())
        + (a * a / (2.0 * outer.biaxial()) + b * b / (2.0 * outer.shear)) / (b * b - a * a);
    -(free(&inner) - free(&outer)) / compliance
}

/// Plane-strain Rayleigh wave speed of an elastic half-space (K, G, ρ): the root
/// ξ = c_R/c_S in (0, 1) of (2 − ξ²)² = 4 √(1 − κ²ξ²) √(1 − ξ²), κ = c_S/c_L.
pub fn rayleigh_speed(bulk: f64, shear: f64, density: f64) -> f64 {
    let cs = (shear / density).sqrt();
    let cl = ((bulk + 4.0 * shear / 3.0) / density).sqrt();
    let k2 = (cs / cl).powi(2);
    let f = |x: f64| {
        let x2 = x * x;
        (2.0 - x2).powi(2) - 4.0 * (1.0 - k2 * x2).sqrt() * (1.0 - x2).sqrt()
    };
    // f < 0 just above 0 (f ≈ −2ξ²(1 − κ²)) and f(1) = 1: one root in between.
    let (mut lo, mut hi) = (1e-6, 1.0);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if f(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi) * cs
}

/// Least-squares slope and intercept of y(x); NaN with fewer than two distinct x.
pub fn line_fit(x: &[f64], y: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    if x.len() < 2 {
        return (f64::NAN, f64::NAN);
    }
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    let slope = sxy / sxx;
    (slope, my - slope * mx)
}

/// The first time in [t0, t1] at which `f` reaches `level` (scanned in `steps` steps,
/// then bisected); NaN if it never does.
pub fn first_time(f: impl Fn(f64) -> f64, level: f64, t0: f64, t1: f64, steps: usize) -> f64 {
    let dt = (t1 - t0) / steps as f64;
    let mut prev = t0;
    if f(t0) >= level {
        return t0;
    }
    for k in 1..=steps {
        let t = t0 + k as f64 * dt;
        if f(t) >= level {
            let (mut lo, mut hi) = (prev, t);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if f(mid) >= level {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            return 0.5 * (lo + hi);
        }
        prev = t;
    }
    f64::NAN
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rayleigh_speed_of_the_paper_material() {
        // mpm_analytic_check.py: K = 1, G = 0.5, ρ = 1 → c_R = 0.6542.
        let c = rayleigh_speed(1.0, 0.5, 1.0);
        assert!((c - 0.6542).abs() < 5e-5, "{c}");
        // ν = 1/4 (K = 5G/3): the textbook ξ = 0.9194.
        let c = rayleigh_speed(5.0 / 3.0, 1.0, 1.0);
        assert!((c - 0.919_40).abs() < 5e-5, "{c}");
    }

    #[test]
    fn concentric_cylinders_match_the_equal_moduli_form() {
        // physics.md §3.2: σ_rr(a) = −0.9 α ΔT (1 − a²/b²) for K = 1, G = 0.5.
        let layer = |alpha_dt| Layer {
            bulk: 1.0,
            shear: 0.5,
            alpha_dt,
        };
        let s = concentric_interface_stress(0.5, 1.0, layer(-1e-2), layer(0.0));
        assert!((s - 6.75e-3).abs() < 1e-12, "{s}");
        // Heating both equally leaves the pair stress-free.
        let s = concentric_interface_stress(0.5, 1.0, layer(1e-2), layer(1e-2));
        assert!(s.abs() < 1e-15);
    }

    #[test]
    fn first_time_finds_a_crossing() {
        let t = first_time(|t| t * t, 2.0, 0.0, 10.0, 100);
        assert!((t - 2f64.sqrt()).abs() < 1e-9);
        assert!(first_time(|t| t, 20.0, 0.0, 10.0, 100).is_nan());
    }
}
