//! Constitutive models, per body: hypo-elastic linear elasticity with an objective
//! (Hughes–Winget) rotation, and compressible Neo-Hookean hyperelasticity. Plane strain:
//! F_zz = 1, D_zz = 0, and σ_zz is carried because pressure and energy need it.

use glam::DMat2;
use serde::{Deserialize, Serialize};

/// A material, chosen per body in the scenario (`model = ...`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "model", rename_all = "snake_case", deny_unknown_fields)]
pub enum Material {
    /// Small-strain isotropic elasticity in rate form, σ̇ = λ tr(D) I + 2G D, with the
    /// stress rotated by the Hughes–Winget increment so rigid rotation leaves it unchanged.
    LinearElastic {
        /// Name bodies refer to.
        name: String,
        /// Density ρ (kg/m³).
        density: f64,
        /// Bulk modulus K (Pa).
        bulk: f64,
        /// Shear modulus G (Pa).
        shear: f64,
    },
    /// Compressible Neo-Hookean: σ = (K/2)(J − 1/J) I + (G/J) dev(J^(-2/3) F Fᵀ).
    NeoHookean {
        /// Name bodies refer to.
        name: String,
        /// Density in the reference state (kg/m³).
        density: f64,
        /// Bulk modulus K (Pa) of the linearised response.
        bulk: f64,
        /// Shear modulus G (Pa) of the linearised response.
        shear: f64,
    },
}

/// Cauchy stress in plane strain (Pa): the in-plane tensor and the out-of-plane σ_zz.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stress {
    /// σ_xx.
    pub xx: f64,
    /// σ_yy.
    pub yy: f64,
    /// σ_xy.
    pub xy: f64,
    /// σ_zz.
    pub zz: f64,
}

impl Stress {
    /// Pressure, −tr σ / 3 (positive in compression).
    pub fn pressure(&self) -> f64 {
        -(self.xx + self.yy + self.zz) / 3.0
    }

    /// In-plane principal stress difference σ₁ − σ₂ ≥ 0 (what photoelasticity shows).
    pub fn principal_difference(&self) -> f64 {
        let d = 0.5 * (self.xx - self.yy);
        2.0 * (d * d + self.xy * self.xy).sqrt()
    }

    /// Energy density of a linear elastic state with this stress: p²/(2K) + s:s/(4G).
    pub fn linear_energy_density(&self, bulk: f64, shear: f64) -> f64 {
        let m = (self.xx + self.yy + self.zz) / 3.0;
        let (a, b, c) = (self.xx - m, self.yy - m, self.zz - m);
        m * m / (2.0 * bulk) + (a * a + b * b + c * c + 2.0 * self.xy * self.xy) / (4.0 * shear)
    }
}

impl Material {
    /// The material's name.
    pub fn name(&self) -> &str {
        match self {
            Material::LinearElastic { name, .. } | Material::NeoHookean { name, .. } => name,
        }
    }

    /// Density (kg/m³).
    pub fn density(&self) -> f64 {
        match *self {
            Material::LinearElastic { density, .. } | Material::NeoHookean { density, .. } => {
                density
            }
        }
    }

    /// (K, G).
    pub fn moduli(&self) -> (f64, f64) {
        match *self {
            Material::LinearElastic { bulk, shear, .. }
            | Material::NeoHookean { bulk, shear, .. } => (bulk, shear),
        }
    }

    /// Plane-strain dilatational wave speed √((K + 4G/3)/ρ) of the undeformed material.
    pub fn wave_speed(&self) -> f64 {
        let (k, g) = self.moduli();
        ((k + 4.0 * g / 3.0) / self.density()).sqrt()
    }

    /// Advances `f` and `stress` over `dt` under the velocity gradient `l` (∂v_i/∂x_j,
    /// column j of the matrix holds ∂v/∂x_j).
    #[inline(always)]
    pub fn update(&self, l: DMat2, dt: f64, f: &mut DMat2, stress: &mut Stress) {
        // Cayley (midpoint) increment: second order, and exactly orthogonal under pure
        // spin, so a rolling body's volume does not drift.
        let half = 0.5 * dt * l;
        *f = (DMat2::IDENTITY - half).inverse() * (DMat2::IDENTITY + half) * *f;
        match *self {
            Material::LinearElastic { bulk, shear, .. } => {
                let (dxx, dyy) = (l.x_axis.x, l.y_axis.y);
                let dxy = 0.5 * (l.y_axis.x + l.x_axis.y);
                // Spin: ω = W_xy = ½(∂vx/∂y − ∂vy/∂x); the Hughes–Winget increment
                // (I − ½ΔtW)⁻¹(I + ½ΔtW) is an exact rotation [[c, s], [−s, c]].
                let a = 0.5 * dt * 0.5 * (l.y_axis.x - l.x_axis.y);
                let inv = 1.0 / (1.0 + a * a);
                let (c, s) = ((1.0 - a * a) * inv, 2.0 * a * inv);
                let (xx, yy, xy) = (stress.xx, stress.yy, stress.xy);
                // Q σ Qᵀ with Q = [[c, s], [−s, c]].
                let rxx = c * c * xx + 2.0 * c * s * xy + s * s * yy;
                let ryy = s * s * xx - 2.0 * c * s * xy + c * c * yy;
                let rxy = (c * c - s * s) * xy + c * s * (yy - xx);
                let lambda = bulk - 2.0 * shear / 3.0;
                let vol = lambda * (dxx + dyy) * dt;
                stress.xx = rxx + vol + 2.0 * shear * dxx * dt;
                stress.yy = ryy + vol + 2.0 * shear * dyy * dt;
                stress.xy = rxy + 2.0 * shear * dxy * dt;
                stress.zz += vol;
            }
            Material::NeoHookean { bulk, shear, .. } => {
                *stress = neo_hookean_stress(*f, bulk, shear);
            }
        }
    }

    /// Stored energy of a particle of reference volume `vol0` with deformation `f` and
    /// stress `stress` (J per unit thickness).
    #[inline]
    pub fn energy(&self, vol0: f64, f: DMat2, stress: &Stress) -> f64 {
        match *self {
            Material::LinearElastic { bulk, shear, .. } => {
                vol0 * f.determinant() * stress.linear_energy_density(bulk, shear)
            }
            Material::NeoHookean { bulk, shear, .. } => {
                let j = f.determinant();
                let b = f * f.transpose();
                let c = j.cbrt();
                let tr = (b.x_axis.x + b.y_axis.y + 1.0) / (c * c);
                vol0 * (0.5 * bulk * (0.5 * (j * j - 1.0) - j.ln()) + 0.5 * shear * (tr - 3.0))
            }
        }
    }
}

/// Cauchy stress of the compressible Neo-Hookean model in plane strain (b_zz = 1).
pub fn neo_hookean_stress(f: DMat2, bulk: f64, shear: f64) -> Stress {
    let j = f.determinant();
    let b = f * f.transpose();
    // J^(-2/3) through cbrt: pow is several times slower and this runs per point.
    let c = j.cbrt();
    let scale = 1.0 / (c * c);
    let (bxx, byy, bxy, bzz) = (
        scale * b.x_axis.x,
        scale * b.y_axis.y,
        scale * b.x_axis.y,
        scale,
    );
    let mean = (bxx + byy + bzz) / 3.0;
    let p = 0.5 * bulk * (j - 1.0 / j);
    let g = shear / j;
    Stress {
        xx: p + g * (bxx - mean),
        yy: p + g * (byy - mean),
        xy: g * bxy,
        zz: p + g * (bzz - mean),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lin() -> Material {
        Material::LinearElastic {
            name: "a".into(),
            density: 1.0,
            bulk: 1.0,
            shear: 0.5,
        }
    }

    fn nh() -> Material {
        Material::NeoHookean {
            name: "b".into(),
            density: 1.0,
            bulk: 1.0,
            shear: 0.5,
        }
    }

    #[test]
    fn rigid_rotation_leaves_stress_invariants_unchanged() {
        for m in [lin(), nh()] {
            let mut f = DMat2::IDENTITY;
            let mut s = Stress::default();
            // Pre-strain uniaxially, then spin a quarter turn in many small steps.
            let stretch = DMat2::from_cols_array(&[0.01, 0.0, 0.0, 0.0]);
            m.update(stretch, 1.0, &mut f, &mut s);
            let (p0, d0) = (s.pressure(), s.principal_difference());
            let w = 1.0;
            let spin = DMat2::from_cols_array(&[0.0, w, -w, 0.0]);
            let n = 2000;
            for _ in 0..n {
                m.update(spin, std::f64::consts::FRAC_PI_2 / n as f64, &mut f, &mut s);
            }
            assert!((s.pressure() - p0).abs() < 1e-4 * p0.abs(), "{m:?}");
            assert!((s.principal_difference() - d0).abs() < 1e-3 * d0, "{m:?}");
            // After a quarter turn the stretched axis is y.
            assert!(s.yy.abs() > s.xx.abs(), "{s:?}");
        }
    }

    #[test]
    fn small_strain_limits_agree() {
        let l = DMat2::from_cols_array(&[1e-4, 3e-5, 3e-5, -2e-4]);
        let (mut f1, mut f2) = (DMat2::IDENTITY, DMat2::IDENTITY);
        let (mut s1, mut s2) = (Stress::default(), Stress::default());
        lin().update(l, 1.0, &mut f1, &mut s1);
        nh().update(l, 1.0, &mut f2, &mut s2);
        for (a, b) in [
            (s1.xx, s2.xx),
            (s1.yy, s2.yy),
            (s1.xy, s2.xy),
            (s1.zz, s2.zz),
        ] {
            assert!((a - b).abs() < 1e-3 * 2e-4, "{s1:?} vs {s2:?}");
        }
        let e1 = lin().energy(1.0, f1, &s1);
        let e2 = nh().energy(1.0, f2, &s2);
        assert!((e1 - e2).abs() < 1e-3 * e1, "{e1} vs {e2}");
    }

    #[test]
    fn wave_speed_plane_strain() {
        assert!((lin().wave_speed() - 1.2910).abs() < 1e-4);
    }
}
