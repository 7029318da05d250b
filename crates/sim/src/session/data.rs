//! What a [`super::Session`] hands out: copies of the particles in id order, the
//! contacts, an MPM run's points and a FEM–DEM run's charge, and borrowed fields for
//! zero-copy views.

use glam::DVec2;
use grains_dem::forces::contact_law;
use grains_dem::{Particles, Setup, State};

/// Particles in id order (copies). Fields an engine does not have are `None` (MPM
/// points have no spin, and their forces live on the grid).
#[derive(Clone, Debug, Default)]
pub struct ParticleData {
    /// Ids, ascending.
    pub id: Vec<u32>,
    /// Positions (m).
    pub pos: Vec<DVec2>,
    /// Velocities (m/s).
    pub vel: Vec<DVec2>,
    /// Angular velocities (rad/s).
    pub omega: Option<Vec<f64>>,
    /// Radii (m); for material points, the radius of a disk of the point's volume.
    pub radius: Vec<f64>,
    /// Masses (kg/m).
    pub mass: Vec<f64>,
    /// Forces at the last evaluation (N/m).
    pub force: Option<Vec<DVec2>>,
    /// Torques at the last evaluation (N).
    pub torque: Option<Vec<f64>>,
}

/// The storage index of each id, in id order: `order[k]` holds the particle with the
/// k-th smallest id. Dense ids (0..n, the engines' creation order) take one pass.
pub fn id_order(ids: &[u32]) -> Vec<usize> {
    let n = ids.len();
    let mut order = vec![usize::MAX; n];
    let dense = ids.iter().enumerate().all(|(i, &id)| {
        let slot = order.get_mut(id as usize);
        match slot {
            Some(s) if *s == usize::MAX => {
                *s = i;
                true
            }
            _ => false,
        }
    });
    if !dense {
        order = (0..n).collect();
        order.sort_unstable_by_key(|&i| ids[i]);
    }
    order
}

/// `values` taken in `order` (in parallel: the reads jump through memory).
pub fn gather<T: Copy + Send + Sync>(values: &[T], order: &[usize]) -> Vec<T> {
    use rayon::prelude::*;
    order.par_iter().map(|&i| values[i]).collect()
}

impl ParticleData {
    /// DEM particles (a DEM run's, or a FEM–DEM run's ring) in id order.
    pub fn of_dem(p: &Particles) -> Self {
        let o = id_order(&p.id);
        ParticleData {
            id: gather(&p.id, &o),
            pos: gather(&p.pos, &o),
            vel: gather(&p.vel, &o),
            omega: Some(gather(&p.omega, &o)),
            radius: gather(&p.radius, &o),
            mass: {
                use rayon::prelude::*;
                o.par_iter().map(|&i| p.mass(i)).collect()
            },
            force: Some(gather(&p.force, &o)),
            torque: Some(gather(&p.torque, &o)),
        }
    }

    /// Any engine's particles as the driver sees them, in id order.
    pub fn of_view(v: &crate::driver::ParticleView) -> Self {
        let o = id_order(v.id);
        ParticleData {
            id: gather(v.id, &o),
            pos: gather(v.pos, &o),
            vel: gather(v.vel, &o),
            radius: gather(&v.radius, &o),
            mass: gather(&v.mass, &o),
            ..Default::default()
        }
    }
}

/// The touching pairs of a DEM state (walls left out), one entry per pair, forces on the
/// first particle of the pair (the second gets their opposite).
#[derive(Clone, Debug, Default)]
pub struct Contacts {
    /// Id of the first particle.
    pub i: Vec<u32>,
    /// Id of the second.
    pub j: Vec<u32>,
    /// Overlap (m).
    pub overlap: Vec<f64>,
    /// Normal force on i (N/m).
    pub normal_force: Vec<DVec2>,
    /// Tangential force on i (N/m).
    pub tangential_force: Vec<DVec2>,
    /// Branch vector from i's centre to j's (minimum image on periodic axes) (m).
    pub branch: Vec<DVec2>,
}

impl Contacts {
    /// The touching pairs of `s`, forces evaluated by the contact law with the stored
    /// tangential springs (not advanced), as the particle stress evaluates them.
    pub fn of(setup: &Setup, s: &State) -> Self {
        let (p, list) = (&s.particles, &s.contacts);
        let mut c = Contacts::default();
        if list.row.len() != p.len() + 1 {
            return c;
        }
        for i in 0..p.len() {
            for e in list.row[i] as usize..list.row[i + 1] as usize {
                let j = list.nbr[e] as usize;
                let d = setup.domain.min_image(p.pos[j] - p.pos[i]);
                let dist = d.length();
                let overlap = p.radius[i] + p.radius[j] - dist;
                if overlap <= 0.0 || dist == 0.0 {
                    continue;
                }
                let n = d / dist;
                let pp = setup
                    .pairs
                    .get(p.material[i] as usize, p.material[j] as usize);
                let m_eff = 1.0 / (p.inv_mass[i] + p.inv_mass[j]);
                let spin = p.radius[i] * p.omega[i] + p.radius[j] * p.omega[j];
                let v = p.vel[i] - p.vel[j];
                let f = contact_law(pp, m_eff, n, overlap, v, spin, list.shear[e], 0.0);
                c.i.push(p.id[i]);
                c.j.push(p.id[j]);
                c.overlap.push(overlap);
                c.normal_force.push(-f.normal * n);
                c.tangential_force.push(f.tangential * n.perp());
                c.branch.push(d);
            }
        }
        c
    }
}

/// An MPM run's material points in id order.
#[derive(Clone, Debug, Default)]
pub struct Points {
    /// Ids.
    pub id: Vec<u32>,
    /// Body index of each point (the scenario's order).
    pub body: Vec<u16>,
    /// Positions (m).
    pub pos: Vec<DVec2>,
    /// Velocities (m/s).
    pub vel: Vec<DVec2>,
    /// Masses (kg/m).
    pub mass: Vec<f64>,
    /// Volumes (m²).
    pub volume: Vec<f64>,
    /// Cauchy stress (xx, yy, xy) (Pa).
    pub stress: Vec<[f64; 3]>,
}

impl Points {
    /// The points of `p`, in id order.
    pub fn of(p: &grains_mpm::Particles) -> Self {
        let o = id_order(&p.id);
        Points {
            id: gather(&p.id, &o),
            body: gather(&p.body, &o),
            pos: gather(&p.pos, &o),
            vel: gather(&p.vel, &o),
            mass: gather(&p.mass, &o),
            volume: o.iter().map(|&i| p.volume(i)).collect(),
            stress: o
                .iter()
                .map(|&i| {
                    let s = p.stress[i];
                    [s.xx, s.yy, s.xy]
                })
                .collect(),
        }
    }
}

/// A FEM–DEM run's charge.
#[derive(Clone, Debug, Default)]
pub struct ChargeData {
    /// Node positions (m).
    pub node_pos: Vec<DVec2>,
    /// Node velocities (m/s).
    pub node_vel: Vec<DVec2>,
    /// Triangles (node indices).
    pub triangles: Vec<[u32; 3]>,
    /// Pressure of each triangle (Pa).
    pub pressure: Vec<f64>,
}

impl ChargeData {
    /// The charge's nodes and elements as they are now.
    pub fn of(c: &grains_fem::Charge) -> Self {
        ChargeData {
            node_pos: c.nodes.pos.clone(),
            node_vel: c.nodes.vel.clone(),
            triangles: c.elems.tri.clone(),
            pressure: c.elems.pressure.clone(),
        }
    }
}

/// An engine's own storage of one particle field (storage order, not id order), for a
/// zero-copy view.
#[derive(Clone, Copy, Debug)]
pub enum Field<'a> {
    /// Ids.
    Ids(&'a [u32]),
    /// One number per particle.
    Scalar(&'a [f64]),
    /// A vector per particle.
    Vector(&'a [DVec2]),
}

/// The fields a view can show, by name.
pub const VIEW_FIELDS: [&str; 6] = ["id", "position", "velocity", "omega", "radius", "force"];

/// Field `name` of DEM particles, if there is one.
pub fn dem_field<'a>(p: &'a Particles, name: &str) -> Option<Field<'a>> {
    Some(match name {
        "id" => Field::Ids(&p.id),
        "position" => Field::Vector(&p.pos),
        "velocity" => Field::Vector(&p.vel),
        "omega" => Field::Scalar(&p.omega),
        "radius" => Field::Scalar(&p.radius),
        "force" => Field::Vector(&p.force),
        _ => return None,
    })
}
