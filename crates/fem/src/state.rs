//! The evolving charge: nodes and elements stored per field, with the node → element
//! index that lets forces be gathered (not scattered) in parallel.

use crate::mesh::{signed_area, Mesh};
use crate::setup::FemSetup;
use glam::DVec2;

/// Per-node fields.
#[derive(Clone, Debug, Default)]
pub struct Nodes {
    /// Position (m).
    pub pos: Vec<DVec2>,
    /// Position at the start of the current step (m).
    pub pos_prev: Vec<DVec2>,
    /// Velocity (m/s): v^(n+½) between the two half kicks, v^n after them.
    pub vel: Vec<DVec2>,
    /// Lumped mass per unit thickness (kg/m): a third of each adjoining element (Eq. A3).
    pub mass: Vec<f64>,
    /// Internal force from the element stresses (N/m).
    pub f_int: Vec<DVec2>,
    /// External force, set by a coupling before the closing kick (N/m).
    pub f_ext: Vec<DVec2>,
    /// Non-viscous damping force of Eq. A5 (N/m).
    pub f_damp: Vec<DVec2>,
}

/// Per-element fields (constant-strain triangles, one integration point).
#[derive(Clone, Debug, Default)]
pub struct Elements {
    /// Node indices, counter-clockwise.
    pub tri: Vec<[u32; 3]>,
    /// Mass per unit thickness (kg/m).
    pub mass: Vec<f64>,
    /// Initial area (m²); relative volume V = area / area_ref.
    pub area_ref: Vec<f64>,
    /// Current area (m²).
    pub area: Vec<f64>,
    /// Specific internal energy e (J/kg), 0 for the reactant at rest; the products'
    /// energy is e + Q.
    pub energy: Vec<f64>,
    /// Pressure from the EOS (Pa).
    pub pressure: Vec<f64>,
    /// Artificial viscosity of the last step (Pa).
    pub q: Vec<f64>,
    /// Deviatoric stress (s_xx, s_yy, s_xy) (Pa); s_zz = −(s_xx + s_yy).
    pub dev: Vec<[f64; 3]>,
    /// Burn fraction λ ∈ [0, 1].
    pub lambda: Vec<f64>,
    /// Lighting time t_l = |x_c − x_d|/D + t0 (s).
    pub t_light: Vec<f64>,
    /// Burn length d_eff = width × A/L_max (m), LS-DYNA's burn length in 2D.
    pub d_eff: Vec<f64>,
    /// Distance of the initial centroid from the detonation point (m).
    pub r_light: Vec<f64>,
    /// Sound speed (m/s).
    pub sound: Vec<f64>,
    /// First time the pressure reached half the CJ pressure (s); NaN before.
    pub arrival: Vec<f64>,
    /// Stable time step of the element at its last update (s).
    pub dt_stable: Vec<f64>,
    /// Force of the element on each of its nodes (scratch for the gather).
    pub f_node: Vec<[DVec2; 3]>,
}

/// The charge: mesh, state and the running energy ledger.
#[derive(Clone, Debug, Default)]
pub struct Charge {
    /// Nodes.
    pub nodes: Nodes,
    /// Elements.
    pub elems: Elements,
    /// Boundary edges, counter-clockwise (outward normal on the right).
    pub boundary: Vec<[u32; 2]>,
    /// Entries of node n are `node_entry[node_row[n]..node_row[n+1]]`, each
    /// `3 × element + local index`.
    pub node_row: Vec<u32>,
    /// See `node_row`.
    pub node_entry: Vec<u32>,
    /// Simulated time (s).
    pub time: f64,
    /// Steps taken.
    pub step: u64,
    /// Smallest element stable time step at the last update (s).
    pub dt_stable: f64,
    /// Work done on the nodes by external forces so far (J/m).
    pub work_external: f64,
    /// Work done on the nodes by the damping forces so far (J/m, ≤ 0).
    pub work_damping: f64,
}

/// Element size used for the burn length and the viscosity: √(2A), the leg of the
/// right isosceles triangle of that area (0.93 × the side of an equilateral one).
#[inline]
pub fn element_size(area: f64) -> f64 {
    (2.0 * area).sqrt()
}

impl Charge {
    /// A charge at rest, unreacted, on `mesh`.
    pub fn new(setup: &FemSetup, mesh: &Mesh) -> Self {
        let x = &setup.explosive;
        let nn = mesh.nodes.len();
        let ne = mesh.tris.len();
        let mut c = Charge {
            boundary: mesh.boundary.clone(),
            ..Default::default()
        };
        let n = &mut c.nodes;
        n.pos.clone_from(&mesh.nodes);
        n.pos_prev.clone_from(&mesh.nodes);
        n.vel = vec![DVec2::ZERO; nn];
        n.mass = vec![0.0; nn];
        n.f_int = vec![DVec2::ZERO; nn];
        n.f_ext = vec![DVec2::ZERO; nn];
        n.f_damp = vec![DVec2::ZERO; nn];
        let el = &mut c.elems;
        el.tri.clone_from(&mesh.tris);
        for t in &mesh.tris {
            let p = t.map(|i| mesh.nodes[i as usize]);
            let a = signed_area(p[0], p[1], p[2]);
            let m = x.density * a;
            for &i in t {
                n.mass[i as usize] += m / 3.0;
            }
            let centroid = (p[0] + p[1] + p[2]) / 3.0;
            let r = (centroid - setup.det_point).length();
            el.mass.push(m);
            el.area_ref.push(a);
            el.area.push(a);
            el.r_light.push(r);
            el.t_light.push(r / x.detonation_velocity + setup.burn.time);
            el.d_eff.push(setup.burn.width * 0.5 * min_altitude(p, a));
            el.dt_stable.push(stable_dt_at_rest(setup, p, a));
        }
        el.energy = vec![0.0; ne];
        el.pressure = vec![0.0; ne];
        el.q = vec![0.0; ne];
        el.dev = vec![[0.0; 3]; ne];
        el.lambda = vec![0.0; ne];
        el.sound = vec![x.unreacted.c0; ne];
        el.arrival = vec![f64::NAN; ne];
        el.f_node = vec![[DVec2::ZERO; 3]; ne];
        // Node → element entries (CSR), in element order so every gather sums the same way.
        let mut count = vec![0u32; nn + 1];
        for t in &mesh.tris {
            for &i in t {
                count[i as usize + 1] += 1;
            }
        }
        for k in 0..nn {
            count[k + 1] += count[k];
        }
        let mut fill = count.clone();
        c.node_entry = vec![0; 3 * ne];
        for (e, t) in mesh.tris.iter().enumerate() {
            for (k, &i) in t.iter().enumerate() {
                c.node_entry[fill[i as usize] as usize] = (3 * e + k) as u32;
                fill[i as usize] += 1;
            }
        }
        c.node_row = count;
        c.dt_stable = c
            .elems
            .dt_stable
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        c
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.nodes.pos.len()
    }

    /// Number of elements.
    pub fn n_elems(&self) -> usize {
        self.elems.tri.len()
    }

    /// Total mass (kg/m).
    pub fn mass(&self) -> f64 {
        self.elems.mass.iter().sum()
    }

    /// The time step the next step may take: safety × the smallest element step.
    pub fn next_dt(&self, setup: &FemSetup) -> f64 {
        setup.safety * self.dt_stable
    }
}

/// The smallest altitude of a triangle, 2A / longest edge: the distance a wave must
/// cross, which sets its stable time step.
#[inline]
pub fn min_altitude(p: [DVec2; 3], area: f64) -> f64 {
    let l = (p[1] - p[0])
        .length_squared()
        .max((p[2] - p[1]).length_squared())
        .max((p[0] - p[2]).length_squared())
        .sqrt();
    2.0 * area / l
}

/// Before the burn reaches it an element still signals at D: the programmed burn
/// front moves at that speed whatever the reactant's own sound speed.
fn stable_dt_at_rest(setup: &FemSetup, p: [DVec2; 3], area: f64) -> f64 {
    let x = &setup.explosive;
    min_altitude(p, area) / x.detonation_velocity.max(x.unreacted.c0)
}
