//! What a [`super::Session`] hands out: copies of the particles in id order, the
//! contacts, an MPM run's points and a FEM–DEM run's charge, and borrowed fields for
//! zero-copy views. 2D runs hand out 2-vectors and scalar spins (the defaults of the
//! generic types), 3D runs 3-vectors for both.

use glam::{DVec2, DVec3};
use grains_dem::{Particles, Setup, State};

/// Particles in id order (copies), vectors `V` and spins `A` (2D: `DVec2` and `f64`;
/// 3D: [`ParticleData3`]). Fields an engine does not have are `None` (MPM points have
/// no spin, and their forces live on the grid).
#[derive(Clone, Debug)]
pub struct ParticleData<V = DVec2, A = f64> {
    /// Ids, ascending.
    pub id: Vec<u32>,
    /// Positions (m).
    pub pos: Vec<V>,
    /// Velocities (m/s).
    pub vel: Vec<V>,
    /// Angular velocities (rad/s).
    pub omega: Option<Vec<A>>,
    /// Radii (m); for material points, the radius of a disk of the point's volume.
    pub radius: Vec<f64>,
    /// Masses (2D: kg/m; 3D: kg).
    pub mass: Vec<f64>,
    /// Forces at the last evaluation (2D: N/m; 3D: N).
    pub force: Option<Vec<V>>,
    /// Torques at the last evaluation (2D: N; 3D: N m).
    pub torque: Option<Vec<A>>,
}

/// The spheres of a 3D run in id order.
pub type ParticleData3 = ParticleData<DVec3, DVec3>;

impl<V, A> Default for ParticleData<V, A> {
    fn default() -> Self {
        ParticleData {
            id: Vec::new(),
            pos: Vec::new(),
            vel: Vec::new(),
            omega: None,
            radius: Vec::new(),
            mass: Vec::new(),
            force: None,
            torque: None,
        }
    }
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

/// How a storage order maps to id order, found once per copy.
pub enum IdOrder {
    /// The ids are a permutation of 0..n (the engines' creation ids): the particle stored
    /// at i belongs in slot `ids[i]`, so a copy is one pass of sequential reads.
    Dense,
    /// Any other ids: `order[k]` is the storage index of the k-th smallest id.
    Sorted(Vec<usize>),
}

impl IdOrder {
    /// Tells dense ids from others in one parallel pass over a bitmap of n bits (it stays
    /// in cache where an index array of n entries would not).
    pub fn of(ids: &[u32]) -> Self {
        use rayon::prelude::*;
        use std::sync::atomic::{AtomicU64, Ordering};
        let n = ids.len();
        let seen: Vec<AtomicU64> = (0..n.div_ceil(64)).map(|_| AtomicU64::new(0)).collect();
        let dense = ids.par_iter().with_min_len(4096).all(|&id| {
            let id = id as usize;
            id < n && {
                let bit = 1u64 << (id % 64);
                seen[id / 64].fetch_or(bit, Ordering::Relaxed) & bit == 0
            }
        });
        if dense {
            IdOrder::Dense
        } else {
            IdOrder::Sorted(id_order(ids))
        }
    }

    /// `value(i)` of every stored particle i, in id order.
    #[allow(unsafe_code)] // the dense case writes each slot once from several threads
    pub fn arrange<T: Send + Sync>(
        &self,
        ids: &[u32],
        value: impl Fn(usize) -> T + Sync,
    ) -> Vec<T> {
        use rayon::prelude::*;
        match self {
            IdOrder::Sorted(order) => order.par_iter().map(|&i| value(i)).collect(),
            IdOrder::Dense => {
                let n = ids.len();
                let mut out: Vec<T> = Vec::with_capacity(n);
                let slots = Slots(out.as_mut_ptr());
                ids.par_iter()
                    .with_min_len(4096)
                    .enumerate()
                    .for_each(|(i, &id)| {
                        // SAFETY: `of` found the ids a permutation of 0..n, so each of the
                        // n slots of the allocation is written exactly once, by one thread.
                        unsafe { slots.put(id as usize, value(i)) }
                    });
                // SAFETY: all n slots are written (above).
                unsafe { out.set_len(n) };
                out
            }
        }
    }

    /// Calls `f(i, k)` for each stored particle i and its place k in id order.
    pub fn each(&self, ids: &[u32], mut f: impl FnMut(usize, usize)) {
        match self {
            IdOrder::Dense => ids
                .iter()
                .enumerate()
                .for_each(|(i, &id)| f(i, id as usize)),
            IdOrder::Sorted(order) => order.iter().enumerate().for_each(|(k, &i)| f(i, k)),
        }
    }
}

/// An output buffer written at disjoint places from several threads.
struct Slots<T>(*mut T);

// SAFETY: the buffer is only written, each place by one thread (`IdOrder::arrange`).
#[allow(unsafe_code)]
unsafe impl<T: Send> Sync for Slots<T> {}

#[allow(unsafe_code)]
impl<T> Slots<T> {
    /// Writes `v` at place `k` without reading or dropping what was there.
    ///
    /// # Safety
    /// `k` is inside the allocation and no other thread writes place `k`.
    unsafe fn put(&self, k: usize, v: T) {
        self.0.add(k).write(v)
    }
}

/// DEM particles of either dimension (the engines share their field names) in id
/// order.
macro_rules! dem_particles {
    ($p:expr) => {{
        let p = $p;
        let ids = &p.id;
        let o = IdOrder::of(ids);
        ParticleData {
            id: o.arrange(ids, |i| ids[i]),
            pos: o.arrange(ids, |i| p.pos[i]),
            vel: o.arrange(ids, |i| p.vel[i]),
            omega: Some(o.arrange(ids, |i| p.omega[i])),
            radius: o.arrange(ids, |i| p.radius[i]),
            mass: o.arrange(ids, |i| p.mass(i)),
            force: Some(o.arrange(ids, |i| p.force[i])),
            torque: Some(o.arrange(ids, |i| p.torque[i])),
        }
    }};
}

impl ParticleData3 {
    /// The spheres of a 3D DEM run in id order.
    pub fn of_dem3(p: &grains_dem3d::Particles) -> Self {
        dem_particles!(p)
    }
}

impl ParticleData {
    /// DEM particles (a DEM run's, or a FEM–DEM run's ring) in id order.
    pub fn of_dem(p: &Particles) -> Self {
        dem_particles!(p)
    }

    /// Any engine's particles as the driver sees them, in id order.
    pub fn of_view(v: &crate::driver::ParticleView) -> Self {
        let ids = v.id;
        let o = IdOrder::of(ids);
        ParticleData {
            id: o.arrange(ids, |i| ids[i]),
            pos: o.arrange(ids, |i| v.pos[i]),
            vel: o.arrange(ids, |i| v.vel[i]),
            radius: o.arrange(ids, |i| v.radius[i]),
            mass: o.arrange(ids, |i| v.mass[i]),
            ..Default::default()
        }
    }
}

/// The touching pairs of a DEM state (walls left out), one entry per pair, forces on the
/// first particle of the pair (the second gets their opposite); vectors `V` (2D:
/// `DVec2`, 3D: `DVec3`).
#[derive(Clone, Debug)]
pub struct Contacts<V = DVec2> {
    /// Id of the first particle.
    pub i: Vec<u32>,
    /// Id of the second.
    pub j: Vec<u32>,
    /// Overlap (m).
    pub overlap: Vec<f64>,
    /// Normal force on i (2D: N/m; 3D: N).
    pub normal_force: Vec<V>,
    /// Tangential force on i (2D: N/m; 3D: N).
    pub tangential_force: Vec<V>,
    /// Branch vector from i's centre to j's (minimum image on periodic axes) (m).
    pub branch: Vec<V>,
}

impl<V> Default for Contacts<V> {
    fn default() -> Self {
        Contacts {
            i: Vec::new(),
            j: Vec::new(),
            overlap: Vec::new(),
            normal_force: Vec::new(),
            tangential_force: Vec::new(),
            branch: Vec::new(),
        }
    }
}

/// The touching pairs of a DEM state of either dimension, through the engine's
/// `stress::each_pair_force` (the set-up's contact law, springs as stored).
macro_rules! touching_pairs {
    ($engine:ident, $setup:expr, $state:expr) => {{
        let s = $state;
        let p = &s.particles;
        let mut c = Contacts::default();
        $engine::stress::each_pair_force($setup, s, |f| {
            c.i.push(p.id[f.i]);
            c.j.push(p.id[f.j]);
            c.overlap.push(f.overlap);
            c.normal_force.push(f.normal_force());
            c.tangential_force.push(f.tangential_force());
            c.branch.push(f.branch);
        });
        c
    }};
}

impl Contacts {
    /// The touching pairs of a 2D state `s`.
    pub fn of(setup: &Setup, s: &State) -> Self {
        touching_pairs!(grains_dem, setup, s)
    }
}

impl Contacts<DVec3> {
    /// The touching pairs of a 3D state `s`.
    pub fn of3(setup: &grains_dem3d::Setup, s: &grains_dem3d::State) -> Self {
        touching_pairs!(grains_dem3d, setup, s)
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
        let ids = &p.id;
        let o = IdOrder::of(ids);
        Points {
            id: o.arrange(ids, |i| ids[i]),
            body: o.arrange(ids, |i| p.body[i]),
            pos: o.arrange(ids, |i| p.pos[i]),
            vel: o.arrange(ids, |i| p.vel[i]),
            mass: o.arrange(ids, |i| p.mass[i]),
            volume: o.arrange(ids, |i| p.volume(i)),
            stress: o.arrange(ids, |i| {
                let s = p.stress[i];
                [s.xx, s.yy, s.xy]
            }),
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
    /// A 3-vector per particle (3D runs' vectors and spins).
    Vector3(&'a [DVec3]),
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

/// Field `name` of a 3D run's spheres, if there is one.
pub fn dem3_field<'a>(p: &'a grains_dem3d::Particles, name: &str) -> Option<Field<'a>> {
    Some(match name {
        "id" => Field::Ids(&p.id),
        "position" => Field::Vector3(&p.pos),
        "velocity" => Field::Vector3(&p.vel),
        "omega" => Field::Vector3(&p.omega),
        "radius" => Field::Scalar(&p.radius),
        "force" => Field::Vector3(&p.force),
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::IdOrder;

    /// Both paths give the values sorted by id, and `each` pairs storage with id order.
    #[test]
    fn id_order_by_scatter_and_by_sort() {
        let shuffled: Vec<u32> = (0..10_000u32).map(|k| (k * 7919) % 10_000).collect();
        let gaps: Vec<u32> = shuffled.iter().map(|&id| 3 * id + 1).collect();
        for (ids, dense) in [(shuffled, true), (gaps, false)] {
            let o = IdOrder::of(&ids);
            assert_eq!(matches!(o, IdOrder::Dense), dense);
            let got = o.arrange(&ids, |i| (ids[i], i));
            let mut want: Vec<(u32, usize)> = ids.iter().copied().zip(0..).collect();
            want.sort_unstable();
            assert_eq!(got, want);
            let mut seen = vec![usize::MAX; ids.len()];
            o.each(&ids, |i, k| seen[k] = i);
            assert_eq!(seen, want.iter().map(|w| w.1).collect::<Vec<_>>());
        }
    }

    /// A repeated id is not a permutation.
    #[test]
    fn repeated_ids_are_not_dense() {
        assert!(matches!(IdOrder::of(&[0, 1, 1]), IdOrder::Sorted(_)));
        assert!(matches!(IdOrder::of(&[]), IdOrder::Dense));
    }
}
