//! The element pass: from the nodes' step (x^n → x^(n+1), velocity v^(n+½)) to each
//! element's burn fraction, viscosity, deviatoric stress, energy and pressure at
//! t^(n+1), and from those stresses to the internal nodal forces (Eq. A4 with one
//! integration point per triangle, renewed geometry every step).
//!
//! Energy is updated with the trapezoidal work of pressure and the mid-step viscosity,
//! −(½(p^n + p^(n+1)) + ½(q^(n−½) + q^(n+½)))·ΔA, the same forces the nodes are kicked
//! with, so internal + kinetic energy is conserved to second order. Because every EOS
//! here is linear in e at fixed density, p^(n+1) is solved together with e^(n+1).

use crate::eos::mixture;
use crate::mesh::signed_area;
use crate::setup::FemSetup;
use crate::state::{element_size, min_altitude, Charge};
use glam::DVec2;
use rayon::prelude::*;

/// Elements per parallel task; fixed so results do not depend on the thread count.
const CHUNK: usize = 1024;

/// The step made the mesh unusable.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Breakdown {
    /// An element turned inside out.
    #[error("element {element} inverted (area {area:e} m²) at t = {time:e} s; the step is too large or the mesh too distorted")]
    Inverted {
        /// Element index.
        element: usize,
        /// Its signed area.
        area: f64,
        /// Time.
        time: f64,
    },
    /// A pressure or energy became NaN or infinite.
    #[error("element {element} has a non-finite state at t = {time:e} s")]
    NotFinite {
        /// Element index.
        element: usize,
        /// Time.
        time: f64,
    },
}

struct Chunk<'a> {
    start: usize,
    area: &'a mut [f64],
    energy: &'a mut [f64],
    pressure: &'a mut [f64],
    q: &'a mut [f64],
    dev: &'a mut [[f64; 3]],
    lambda: &'a mut [f64],
    sound: &'a mut [f64],
    arrival: &'a mut [f64],
    dt_stable: &'a mut [f64],
    f_node: &'a mut [[DVec2; 3]],
}

/// Updates every element to time `t1` = time + dt after the nodes drifted, then gathers
/// the internal nodal forces. Sets `dt_stable` to the smallest element step.
pub fn stress_forces(setup: &FemSetup, c: &mut Charge, dt: f64) -> Result<(), Breakdown> {
    let t1 = c.time + dt;
    let el = &mut c.elems;
    let nodes = &c.nodes;
    let (tri, mass, area_ref, t_light, d_eff) =
        (&el.tri, &el.mass, &el.area_ref, &el.t_light, &el.d_eff);
    let mut chunks = Vec::with_capacity(tri.len().div_ceil(CHUNK));
    {
        let mut area = el.area.chunks_mut(CHUNK);
        let mut energy = el.energy.chunks_mut(CHUNK);
        let mut pressure = el.pressure.chunks_mut(CHUNK);
        let mut q = el.q.chunks_mut(CHUNK);
        let mut dev = el.dev.chunks_mut(CHUNK);
        let mut lambda = el.lambda.chunks_mut(CHUNK);
        let mut sound = el.sound.chunks_mut(CHUNK);
        let mut arrival = el.arrival.chunks_mut(CHUNK);
        let mut dts = el.dt_stable.chunks_mut(CHUNK);
        let mut f_node = el.f_node.chunks_mut(CHUNK);
        let mut start = 0;
        for a in area.by_ref() {
            let len = a.len();
            chunks.push(Chunk {
                start,
                area: a,
                energy: energy.next().unwrap(),
                pressure: pressure.next().unwrap(),
                q: q.next().unwrap(),
                dev: dev.next().unwrap(),
                lambda: lambda.next().unwrap(),
                sound: sound.next().unwrap(),
                arrival: arrival.next().unwrap(),
                dt_stable: dts.next().unwrap(),
                f_node: f_node.next().unwrap(),
            });
            start += len;
        }
    }
    let x = &setup.explosive;
    let d_cj = x.detonation_velocity;
    let v_cj = x.v_cj();
    let half_pcj = 0.5 * x.cj_pressure;
    let (cl, cq) = (setup.viscosity.linear, setup.viscosity.quadratic);
    let strength = setup.strength;
    let compression = setup.burn.compression;

    let results: Vec<Result<f64, Breakdown>> = chunks
        .into_par_iter()
        .map(|ch| {
            let mut dt_min = f64::INFINITY;
            for k in 0..ch.area.len() {
                let e = ch.start + k;
                let t = tri[e];
                let x0 = t.map(|i| nodes.pos_prev[i as usize]);
                let x1 = t.map(|i| nodes.pos[i as usize]);
                let v = t.map(|i| nodes.vel[i as usize]);
                let a1 = signed_area(x1[0], x1[1], x1[2]);
                if a1 <= 0.0 || !a1.is_finite() {
                    return Err(Breakdown::Inverted {
                        element: e,
                        area: a1,
                        time: t1,
                    });
                }
                let a0 = ch.area[k];
                let xm = [
                    0.5 * (x0[0] + x1[0]),
                    0.5 * (x0[1] + x1[1]),
                    0.5 * (x0[2] + x1[2]),
                ];
                let am = signed_area(xm[0], xm[1], xm[2]);
                let gm = gradients(xm, am);
                // Velocity gradient L = Σ v_a ⊗ ∇N_a at mid-step geometry.
                let (mut lxx, mut lxy, mut lyx, mut lyy) = (0.0, 0.0, 0.0, 0.0);
                for a in 0..3 {
                    lxx += v[a].x * gm[a].x;
                    lxy += v[a].x * gm[a].y;
                    lyx += v[a].y * gm[a].x;
                    lyy += v[a].y * gm[a].y;
                }
                let d_area = a1 - a0;
                let vol_rate = d_area / (dt * am);
                let m = mass[e];
                let rel_v = a1 / area_ref[e];

                // Burn fraction: time-lit (Eq. A2 in closed form) and compression-lit.
                let mut lam = ch.lambda[k];
                if t1 > t_light[e] {
                    lam = lam.max((t1 - t_light[e]) * d_cj / d_eff[e]);
                }
                if compression && rel_v < 1.0 {
                    lam = lam.max((1.0 - rel_v) / (1.0 - v_cj));
                }
                let lam = lam.min(1.0);

                // Artificial bulk viscosity, in compression only.
                let size = element_size(am);
                let c_old = ch.sound[k];
                let q1 = if vol_rate < 0.0 {
                    (m / am)
                        * (cq * size * size * vol_rate * vol_rate - cl * size * c_old * vol_rate)
                } else {
                    0.0
                };

                // Deviatoric stress (Jaumann rate, von Mises cap), if asked for.
                let s0 = ch.dev[k];
                let (dxx, dyy, dxy) = (lxx, lyy, 0.5 * (lxy + lyx));
                let mut s1 = [0.0; 3];
                let mut w_dev = 0.0;
                if let Some(st) = strength {
                    let keep = if st.products { 1.0 } else { 1.0 - lam };
                    let g = keep * st.shear_modulus;
                    let y = keep * st.yield_stress;
                    let w = 0.5 * (lxy - lyx);
                    let mean = (dxx + dyy) / 3.0;
                    let mut s = [
                        s0[0] + dt * (2.0 * g * (dxx - mean) + 2.0 * w * s0[2]),
                        s0[1] + dt * (2.0 * g * (dyy - mean) - 2.0 * w * s0[2]),
                        s0[2] + dt * (2.0 * g * dxy + w * (s0[1] - s0[0])),
                    ];
                    let szz = -(s[0] + s[1]);
                    let j2 = 0.5 * (s[0] * s[0] + s[1] * s[1] + szz * szz) + s[2] * s[2];
                    let seq = (3.0 * j2).sqrt();
                    if seq > y {
                        let f = if seq > 0.0 { y / seq } else { 0.0 };
                        s = s.map(|v| v * f);
                    }
                    s1 = s;
                    let sb = [
                        0.5 * (s0[0] + s1[0]),
                        0.5 * (s0[1] + s1[1]),
                        0.5 * (s0[2] + s1[2]),
                    ];
                    w_dev = am * dt * (sb[0] * dxx + sb[1] * dyy + 2.0 * sb[2] * dxy);
                }

                // Energy and pressure together: p1 = a + b·e1.
                let mix = mixture(x, lam, rel_v);
                let (pa, pb) = (mix.a, mix.b);
                let q_bar = 0.5 * (ch.q[k] + q1);
                let rhs =
                    ch.energy[k] + (-(0.5 * (ch.pressure[k] + pa) + q_bar) * d_area + w_dev) / m;
                let e1 = rhs / (1.0 + 0.5 * pb * d_area / m);
                let p1 = pa + pb * e1;
                if !(e1.is_finite() && p1.is_finite()) {
                    return Err(Breakdown::NotFinite {
                        element: e,
                        time: t1,
                    });
                }
                let c2 = mix.sound2(x, e1, p1);
                let c = c2.sqrt();

                // Forces on the nodes from σ = −(p + q)I + s at the new geometry.
                let g1 = gradients(x1, a1);
                let ps = p1 + q1;
                let (sxx, syy, sxy) = (s1[0] - ps, s1[1] - ps, s1[2]);
                let mut f = [DVec2::ZERO; 3];
                for a in 0..3 {
                    f[a] = -a1
                        * DVec2::new(sxx * g1[a].x + sxy * g1[a].y, sxy * g1[a].x + syy * g1[a].y);
                }

                // Stable step: the wave crosses the smallest altitude; the burn front
                // still signals at D(1 − λ) where the reactant remains.
                let c_dt = c.max(d_cj * (1.0 - lam));
                let qs = if vol_rate < 0.0 {
                    cl * c_dt + cq * size * vol_rate.abs()
                } else {
                    0.0
                };
                let dte = min_altitude(x1, a1) / (qs + (qs * qs + c_dt * c_dt).sqrt());
                dt_min = dt_min.min(dte);

                if ch.arrival[k].is_nan() && p1 >= half_pcj {
                    ch.arrival[k] = t1;
                }
                ch.area[k] = a1;
                ch.energy[k] = e1;
                ch.pressure[k] = p1;
                ch.q[k] = q1;
                ch.dev[k] = s1;
                ch.lambda[k] = lam;
                ch.sound[k] = c;
                ch.dt_stable[k] = dte;
                ch.f_node[k] = f;
            }
            Ok(dt_min)
        })
        .collect();
    let mut dt_min = f64::INFINITY;
    for r in results {
        dt_min = dt_min.min(r?);
    }
    c.dt_stable = dt_min;
    gather(c);
    Ok(())
}

/// Shape-function gradients ∇N_a of a triangle with (positive) area `area`.
#[inline(always)]
pub fn gradients(p: [DVec2; 3], area: f64) -> [DVec2; 3] {
    let inv = 1.0 / (2.0 * area);
    [
        (p[2] - p[1]).perp() * inv,
        (p[0] - p[2]).perp() * inv,
        (p[1] - p[0]).perp() * inv,
    ]
}

/// Sums each node's share of its elements' forces, in element order.
fn gather(c: &mut Charge) {
    let (row, entry, f_node) = (&c.node_row, &c.node_entry, &c.elems.f_node);
    c.nodes.f_int.par_iter_mut().enumerate().for_each(|(n, f)| {
        let mut s = DVec2::ZERO;
        for &k in &entry[row[n] as usize..row[n + 1] as usize] {
            s += f_node[k as usize / 3][k as usize % 3];
        }
        *f = s;
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gradients_sum_to_zero_and_reproduce_linear_fields() {
        let p = [
            DVec2::new(0.0, 0.0),
            DVec2::new(2.0, 0.1),
            DVec2::new(0.3, 1.5),
        ];
        let a = signed_area(p[0], p[1], p[2]);
        let g = gradients(p, a);
        assert!((g[0] + g[1] + g[2]).length() < 1e-12);
        // u = 3x − 2y: Σ u_a ∇N_a = (3, −2).
        let grad: DVec2 = (0..3).map(|k| (3.0 * p[k].x - 2.0 * p[k].y) * g[k]).sum();
        assert!((grad - DVec2::new(3.0, -2.0)).length() < 1e-12);
    }
}
