//! Frictionless sphere packings at jamming, in a walled box or cylinder: the
//! compress-and-minimise protocol of O'Hern, Silbert, Liu & Nagel (PRE 68, 011306,
//! 2003). Soft spheres with harmonic overlaps, U = ½ Σ (δ_ij / d̄)², start at random
//! places; the packing fraction is stepped up (all radii scaled) while a FIRE
//! minimisation finds U = 0, and bisected down once it cannot: the bisection ends on the
//! lowest fraction with U > 0 found, i.e. just above jamming, where frictionless spheres
//! are isostatic (coordination 2·3 = 6 without rattlers) at random close packing
//! (φ_J ≈ 0.64, less near the walls, which is why φ is also measured in a central
//! sub-volume).
//!
//! Lengths are in units of the mean diameter while packing and scaled back at the end.

use glam::DVec3;
use rand::RngExt;

/// The container.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Container {
    /// The box `[0, size]` walled on every side.
    Box {
        /// Edge lengths (m).
        size: [f64; 3],
    },
    /// The cylinder of `radius` about the z axis through (0, 0), from z = 0 to `height`,
    /// walled at both ends.
    Cylinder {
        /// Radius (m).
        radius: f64,
        /// Height (m).
        height: f64,
    },
}

impl Container {
    fn volume(&self) -> f64 {
        match *self {
            Container::Box { size } => size[0] * size[1] * size[2],
            Container::Cylinder { radius, height } => {
                std::f64::consts::PI * radius * radius * height
            }
        }
    }

    fn scaled(&self, s: f64) -> Container {
        match *self {
            Container::Box { size } => Container::Box {
                size: size.map(|x| x * s),
            },
            Container::Cylinder { radius, height } => Container::Cylinder {
                radius: radius * s,
                height: height * s,
            },
        }
    }

    /// A point drawn uniformly inside.
    fn draw(&self, rng: &mut impl RngExt) -> DVec3 {
        match *self {
            Container::Box { size } => DVec3::new(
                rng.random::<f64>() * size[0],
                rng.random::<f64>() * size[1],
                rng.random::<f64>() * size[2],
            ),
            Container::Cylinder { radius, height } => loop {
                let (x, y) = (
                    2.0 * rng.random::<f64>() - 1.0,
                    2.0 * rng.random::<f64>() - 1.0,
                );
                if x * x + y * y <= 1.0 {
                    break DVec3::new(x * radius, y * radius, rng.random::<f64>() * height);
                }
            },
        }
    }

    /// The overlap of a sphere of radius `r` at `p` with each wall it touches, as
    /// (overlap, unit normal into the container).
    fn touches(&self, p: DVec3, r: f64, mut f: impl FnMut(f64, DVec3)) {
        let mut axis = |x: f64, hi: f64, e: DVec3| {
            if x < r {
                f(r - x, e);
            }
            if hi - x < r {
                f(r - (hi - x), -e);
            }
        };
        match *self {
            Container::Box { size } => {
                axis(p.x, size[0], DVec3::X);
                axis(p.y, size[1], DVec3::Y);
                axis(p.z, size[2], DVec3::Z);
            }
            Container::Cylinder { radius, height } => {
                axis(p.z, height, DVec3::Z);
                let rho = (p.x * p.x + p.y * p.y).sqrt();
                if rho + r > radius && rho > 0.0 {
                    f(rho + r - radius, -DVec3::new(p.x, p.y, 0.0) / rho);
                }
            }
        }
    }

    /// Whether `p` lies in the central sub-volume: the container shrunk by `margin` on
    /// every side.
    fn inner(&self, p: DVec3, margin: f64) -> bool {
        match *self {
            Container::Box { size } => (0..3).all(|a| p[a] > margin && p[a] < size[a] - margin),
            Container::Cylinder { radius, height } => {
                p.z > margin && p.z < height - margin && p.truncate().length() < radius - margin
            }
        }
    }

    fn inner_volume(&self, margin: f64) -> f64 {
        match *self {
            Container::Box { size } => size.iter().map(|s| (s - 2.0 * margin).max(0.0)).product(),
            Container::Cylinder { radius, height } => {
                let r = (radius - margin).max(0.0);
                std::f64::consts::PI * r * r * (height - 2.0 * margin).max(0.0)
            }
        }
    }
}

/// A jammed packing and its measures.
#[derive(Clone, Debug)]
pub struct SpherePacking {
    /// Centres (m).
    pub pos: Vec<DVec3>,
    /// Radii (m).
    pub radius: Vec<f64>,
    /// The container (m).
    pub container: Container,
    /// Solid fraction of the whole container.
    pub phi_bulk: f64,
    /// Solid fraction of the central sub-volume (the container less `margin` on every
    /// side), each sphere's volume cut exactly by no plane: spheres counted whole by
    /// their centre, which is unbiased for a sub-volume many diameters across.
    pub phi_interior: f64,
    /// The margin of the central sub-volume (m).
    pub margin: f64,
    /// Mean contacts per sphere, spheres with fewer than 4 contacts (rattlers, which
    /// carry no load) removed repeatedly; wall contacts included.
    pub coordination: f64,
    /// The same over the spheres whose centre is in the central sub-volume, whose
    /// contacts are with other spheres: 2·3 = 6 for isostatic frictionless spheres.
    pub coordination_interior: f64,
    /// Contacts (sphere pairs and sphere–wall) over the 3 N degrees of freedom of the
    /// spheres that are not rattlers: 1 for an isostatic packing.
    pub isostaticity: f64,
    /// Rattlers (spheres left out of `coordination`).
    pub rattlers: usize,
    /// Eigenvalues of the deviatoric fabric tensor Σ n⊗n / N_c − I/3 over the
    /// sphere–sphere contacts, largest first (0 for an isotropic fabric).
    pub fabric_deviator: [f64; 3],
    /// Minimisations done.
    pub minimisations: u32,
    /// Each sphere's contacts with other spheres and the walls, rattlers' included.
    pub contacts: Vec<u32>,
    /// Whether each sphere is a rattler (left out of `coordination`).
    pub rattler: Vec<bool>,
    /// Whether each sphere's centre lies in the central sub-volume.
    pub interior: Vec<bool>,
}

/// Packs `n` spheres of the bidisperse 50:50 mixture of diameters `d` and `ratio · d`
/// (ratio 1: monodisperse) in `container` to jamming, from the seed `seed`. The
/// container is scaled to hold the spheres at the jamming fraction: only its shape is
/// kept, the spheres keep their diameters.
pub fn jam(n: usize, d: f64, ratio: f64, container: Container, seed: u64) -> SpherePacking {
    let mut rng = grains_core::rng::seeded(seed);
    let d_of = |i: usize| if i.is_multiple_of(2) { 1.0 } else { ratio };
    let mean_d = (0..n).map(d_of).sum::<f64>() / n as f64;
    let mut rad: Vec<f64> = (0..n).map(|i| 0.5 * d_of(i) / mean_d).collect();
    let solid: f64 = rad
        .iter()
        .map(|r| 4.0 / 3.0 * std::f64::consts::PI * r.powi(3))
        .sum();
    // The container in mean-diameter units at φ = 0.64, then held fixed: φ moves with
    // the radii.
    let box_ = container.scaled((solid / 0.64 / container.volume()).cbrt());
    let vol = box_.volume();
    let base = rad.clone();
    let phi_of = |s: f64| solid * s.powi(3) / vol;
    let mut pos: Vec<DVec3> = (0..n).map(|_| box_.draw(&mut rng)).collect();
    let mut phi = 0.3;
    let mut dphi = 0.02;
    let mut minimisations = 0;
    let mut above: Option<(f64, Vec<DVec3>)> = None;
    let scale = |phi: f64, rad: &mut [f64]| {
        let s = (phi / phi_of(1.0)).cbrt();
        for (r, b) in rad.iter_mut().zip(&base) {
            *r = b * s;
        }
    };
    while dphi > 2e-4 {
        scale(phi, &mut rad);
        let mut trial = pos.clone();
        let u = minimise(&mut trial, &rad, &box_);
        minimisations += 1;
        if u / n as f64 > 1e-14 {
            above = Some((phi, trial));
            dphi *= 0.5;
            phi -= dphi;
        } else {
            pos = trial;
            phi += dphi;
            if above.as_ref().is_some_and(|(a, _)| phi >= *a) {
                dphi *= 0.5;
                phi -= dphi;
            }
        }
    }
    let (phi, jammed) = above.unwrap_or((phi, pos));
    scale(phi, &mut rad);
    // Metres per packing unit: the first species' diameter, 1/mean_d · s here, is d.
    let s = (phi / phi_of(1.0)).cbrt();
    measure(jammed, rad, box_, d * mean_d / s, minimisations)
}

/// The measures of a packing in mean-diameter units, scaled by `unit` to metres.
fn measure(
    pos: Vec<DVec3>,
    rad: Vec<f64>,
    box_: Container,
    unit: f64,
    minimisations: u32,
) -> SpherePacking {
    let n = pos.len();
    let mut pairs = Vec::new();
    for i in 0..n {
        for j in i + 1..n {
            if pos[i].distance(pos[j]) < rad[i] + rad[j] {
                pairs.push((i, j));
            }
        }
    }
    let mut walls = vec![0usize; n];
    for i in 0..n {
        box_.touches(pos[i], rad[i], |_, _| walls[i] += 1);
    }
    // Rattlers: fewer than d + 1 = 4 contacts, removed until none is left.
    let mut alive = vec![true; n];
    loop {
        let mut z = walls.clone();
        for &(i, j) in &pairs {
            if alive[i] && alive[j] {
                z[i] += 1;
                z[j] += 1;
            }
        }
        let dead: Vec<usize> = (0..n).filter(|&i| alive[i] && z[i] < 4).collect();
        if dead.is_empty() {
            let live = alive.iter().filter(|&&a| a).count();
            let contacts: usize = (0..n).filter(|&i| alive[i]).map(|i| z[i]).sum();
            let wall_contacts: usize = (0..n).filter(|&i| alive[i]).map(|i| walls[i]).sum();
            let fabric = fabric(&pos, &pairs);
            let margin = 2.0;
            let core: Vec<usize> = (0..n)
                .filter(|&i| alive[i] && box_.inner(pos[i], margin))
                .collect();
            let core_z = core.iter().map(|&i| z[i]).sum::<usize>() as f64;
            let vol_of = |r: f64| 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
            let inner: f64 = (0..n)
                .filter(|&i| box_.inner(pos[i], margin))
                .map(|i| vol_of(rad[i]))
                .sum();
            let solid: f64 = rad.iter().map(|&r| vol_of(r)).sum();
            let mut each = walls.clone();
            for &(i, j) in &pairs {
                each[i] += 1;
                each[j] += 1;
            }
            return SpherePacking {
                contacts: each.iter().map(|&c| c as u32).collect(),
                rattler: alive.iter().map(|a| !a).collect(),
                interior: (0..n).map(|i| box_.inner(pos[i], margin)).collect(),
                phi_bulk: solid / box_.volume(),
                phi_interior: inner / box_.inner_volume(margin),
                margin: margin * unit,
                coordination: contacts as f64 / live.max(1) as f64,
                coordination_interior: core_z / core.len().max(1) as f64,
                // Each pair was counted at both its spheres.
                isostaticity: (contacts + wall_contacts) as f64 / 2.0 / (3 * live.max(1)) as f64,
                rattlers: n - live,
                fabric_deviator: fabric,
                minimisations,
                pos: pos.iter().map(|p| *p * unit).collect(),
                radius: rad.iter().map(|r| r * unit).collect(),
                container: box_.scaled(unit),
            };
        }
        for i in dead {
            alive[i] = false;
        }
    }
}

/// Eigenvalues of Σ n⊗n / N_c − I/3, largest first.
fn fabric(pos: &[DVec3], pairs: &[(usize, usize)]) -> [f64; 3] {
    let mut f = glam::DMat3::ZERO;
    for &(i, j) in pairs {
        let n = (pos[j] - pos[i]).normalize();
        f += glam::DMat3::from_cols(n * n.x, n * n.y, n * n.z);
    }
    let f = f * (1.0 / pairs.len().max(1) as f64) - glam::DMat3::IDENTITY * (1.0 / 3.0);
    let mut e = symmetric_eigenvalues(f);
    e.sort_by(|a, b| b.total_cmp(a));
    e
}

/// Eigenvalues of a symmetric 3 × 3 matrix (the trigonometric closed form).
fn symmetric_eigenvalues(a: glam::DMat3) -> [f64; 3] {
    let q = (a.x_axis.x + a.y_axis.y + a.z_axis.z) / 3.0;
    let p1 = a.y_axis.x.powi(2) + a.z_axis.x.powi(2) + a.z_axis.y.powi(2);
    let p2 =
        (a.x_axis.x - q).powi(2) + (a.y_axis.y - q).powi(2) + (a.z_axis.z - q).powi(2) + 2.0 * p1;
    let p = (p2 / 6.0).sqrt();
    if p == 0.0 {
        return [q; 3];
    }
    let b = (a - glam::DMat3::IDENTITY * q) * (1.0 / p);
    let r = (0.5 * b.determinant()).clamp(-1.0, 1.0);
    let phi = r.acos() / 3.0;
    let e1 = q + 2.0 * p * phi.cos();
    let e3 = q + 2.0 * p * (phi + 2.0 * std::f64::consts::PI / 3.0).cos();
    [e1, 3.0 * q - e1 - e3, e3]
}

/// FIRE minimisation (Bitzek et al. 2006) of U = ½ Σ δ² over pairs and walls; returns U
/// at the end (0 once no two spheres overlap).
fn minimise(pos: &mut [DVec3], rad: &[f64], box_: &Container) -> f64 {
    let n = pos.len();
    let mut vel = vec![DVec3::ZERO; n];
    let mut force = vec![DVec3::ZERO; n];
    let (mut dt, mut alpha, mut since) = (0.05, 0.1, 0u32);
    let mut list = Vec::new();
    let mut built = pos.to_vec();
    let skin = 0.3;
    let rmax = rad.iter().cloned().fold(0.0, f64::max);
    let build = |pos: &[DVec3], list: &mut Vec<(u32, u32)>| {
        list.clear();
        for i in 0..pos.len() {
            for j in i + 1..pos.len() {
                if pos[i].distance_squared(pos[j]) < (2.0 * rmax + skin).powi(2) {
                    list.push((i as u32, j as u32));
                }
            }
        }
    };
    build(pos, &mut list);
    let mut u = 0.0;
    for _ in 0..200_000 {
        if pos
            .iter()
            .zip(&built)
            .any(|(p, b)| p.distance_squared(*b) > 0.25 * skin * skin)
        {
            build(pos, &mut list);
            built.copy_from_slice(pos);
        }
        u = 0.0;
        let mut fmax: f64 = 0.0;
        force.iter_mut().for_each(|f| *f = DVec3::ZERO);
        for &(i, j) in &list {
            let (i, j) = (i as usize, j as usize);
            let d = pos[j] - pos[i];
            let dist = d.length();
            let overlap = rad[i] + rad[j] - dist;
            if overlap > 0.0 && dist > 0.0 {
                u += 0.5 * overlap * overlap;
                let f = d * (overlap / dist);
                force[i] -= f;
                force[j] += f;
            }
        }
        for i in 0..n {
            box_.touches(pos[i], rad[i], |o, e| {
                u += 0.5 * o * o;
                force[i] += e * o;
            });
            fmax = fmax.max(force[i].length());
        }
        // Below U/N ~ 1e-16 the packing has come apart (unjammed), above it with
        // no force left it is jammed.
        if u < 1e-16 * n as f64 || fmax < 1e-12 {
            break;
        }
        let power: f64 = force.iter().zip(&vel).map(|(f, v)| f.dot(*v)).sum();
        if power > 0.0 {
            let vn = vel.iter().map(|v| v.length_squared()).sum::<f64>().sqrt();
            let fnorm = force.iter().map(|f| f.length_squared()).sum::<f64>().sqrt();
            for (v, f) in vel.iter_mut().zip(&force) {
                *v = (1.0 - alpha) * *v + alpha * vn * *f / fnorm;
            }
            since += 1;
            if since > 5 {
                dt = (dt * 1.1f64).min(0.2);
                alpha *= 0.99;
            }
        } else {
            vel.iter_mut().for_each(|v| *v = DVec3::ZERO);
            dt *= 0.5;
            alpha = 0.1;
            since = 0;
        }
        for i in 0..n {
            vel[i] += force[i] * dt;
            pos[i] += vel[i] * dt;
        }
    }
    u
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 400 frictionless bidisperse spheres (1 : 1.4) jammed in a box: random close
    /// packing inside (φ ≈ 0.64 for this mixture, O'Hern et al. 2003) and isostatic
    /// (Z ≈ 6 without rattlers), an isotropic fabric.
    #[test]
    fn frictionless_spheres_jam_at_random_close_packing_isostatic() {
        let p = jam(
            400,
            1e-3,
            1.4,
            Container::Box {
                size: [1.0, 1.0, 1.0],
            },
            3,
        );
        eprintln!(
            "φ {} / {}, Z {} / {}, iso {}, rattlers {}, fabric {:?}, minimisations {}",
            p.phi_bulk,
            p.phi_interior,
            p.coordination,
            p.coordination_interior,
            p.isostaticity,
            p.rattlers,
            p.fabric_deviator,
            p.minimisations
        );
        assert!(
            (0.6..0.67).contains(&p.phi_interior),
            "interior φ {}",
            p.phi_interior
        );
        assert!(
            p.phi_bulk < p.phi_interior,
            "walls loosen: bulk φ {}",
            p.phi_bulk
        );
        let z = p.coordination_interior;
        assert!((5.7..6.5).contains(&z), "interior Z {z}");
        assert!((0.97..1.08).contains(&p.isostaticity), "{}", p.isostaticity);
        assert!(p.fabric_deviator[0] < 0.1, "fabric {:?}", p.fabric_deviator);
    }

    /// The same in a cylinder (its shape kept, scaled to the spheres): the walls
    /// loosen the bulk, the interior jams as in the box.
    #[test]
    fn spheres_jam_in_a_cylinder() {
        let c = Container::Cylinder {
            radius: 1.0,
            height: 2.0,
        };
        let p = jam(400, 2e-3, 1.4, c, 5);
        assert!(
            (0.6..0.67).contains(&p.phi_interior),
            "interior φ {}",
            p.phi_interior
        );
        assert!(p.phi_bulk < p.phi_interior, "bulk φ {}", p.phi_bulk);
        assert!((0.97..1.08).contains(&p.isostaticity), "{}", p.isostaticity);
        let Container::Cylinder { radius, height } = p.container else {
            panic!("{:?}", p.container)
        };
        assert!((height / radius - 2.0).abs() < 1e-12);
        let r_min = p.radius.iter().cloned().fold(f64::MAX, f64::min);
        assert!(
            (r_min - 1e-3).abs() < 1e-12,
            "the small spheres keep d: {r_min}"
        );
    }
}
