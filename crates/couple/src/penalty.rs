//! FEM–DEM contact at the charge's boundary (xue-2019 Appendix C).
//!
//! 1. Coarse detection: the boundary edges are binned into a uniform cell grid; each
//!    particle looks in its cell for edges within r + skin. The candidate list stays
//!    valid while a particle's and a boundary node's displacements since then add up to
//!    at most the skin ([`Coupling::stale`]), and is rebuilt right after the DEM list
//!    (which re-sorts the particles). The skin is wider than the DEM's: the candidates
//!    are a few layers of grains, and a wider skin spares a detection that scans every
//!    grain; the forces do not depend on it (fine detection picks the same contacts in
//!    the same order).
//! 2. Fine detection (Eq. C1): the particle's centre projects inside the edge and lies
//!    within its radius of the edge line, on the outer side or less than a radius inside.
//! 3. Force (Eq. C2 in total form): F = K_pe·(r − d)·n along the edge's outward normal,
//!    on the particle; the reaction −F goes to the edge's two nodes with the linear
//!    shape functions of the projection point (Eq. C3).
//!
//! Beyond Eq. C1, a centre in the wedge outside a convex corner of the boundary, where
//! it projects inside neither edge, touches the corner node itself: without that, grains
//! sink onto the nodes that the gas pushes out between them.

use crate::hits::{self, Hit};
use glam::DVec2;
use grains_dem::comm::{Exchange, Serial};
use grains_dem::Particles;
use grains_fem::Charge;
use rayon::prelude::*;

const CHUNK: usize = 4096;

/// Contact state between the charge's edge and the particles.
#[derive(Clone, Debug, Default)]
pub struct Coupling {
    /// Penalty stiffness K_pe.
    pub stiffness: f64,
    /// Verlet skin (m): edges within r + skin of a particle are its candidates.
    pub skin: f64,
    /// A bound on how far any particle was from the DEM list's build positions when the
    /// candidates were made (m): 0 when made right after a DEM rebuild.
    pub(crate) offset: f64,
    /// Candidate (particle index, boundary edge index) pairs, by particle.
    pub(crate) candidates: Vec<(u32, u32)>,
    /// Boundary node positions at the last coarse detection.
    pub(crate) nodes_at_build: Vec<DVec2>,
    /// The node of each boundary edge's triangle that is not on the edge.
    pub(crate) apex: Vec<u32>,
    /// Coarse detections so far.
    pub builds: u64,
    /// Touching pairs at the last force evaluation.
    pub contacts: usize,
    /// Largest penetration over the particle radius at the last evaluation.
    pub max_penetration_ratio: f64,
    /// The contact of that largest penetration, if any.
    pub deepest: Option<Deepest>,
    /// Energy stored in the penalty springs (J/m).
    pub energy: f64,
    /// Force of the charge on the particles at the last evaluation (N/m), radial sum.
    pub radial_force: f64,
    /// Bound on the squared highest frequency of the penalty springs at the last
    /// evaluation (1/s²); see [`Coupling::stable_dt`].
    pub(crate) omega2_max: f64,
    /// Scratch: each node's Gershgorin row sum.
    node_row: Vec<f64>,
    /// Scratch: the length of edge the grains on each node cover (m).
    cover: Vec<f64>,
    /// The contacts of the last evaluation, on every rank, in ascending (grain id,
    /// edge).
    hits: Vec<Hit>,
    /// Each boundary node's length of edge when the run started: half of each of its
    /// two edges (m).
    pub(crate) node_length: Vec<f64>,
}

impl Coupling {
    /// A coupling of stiffness `stiffness` with Verlet skin `skin`.
    pub fn new(stiffness: f64, skin: f64) -> Self {
        Coupling {
            stiffness,
            skin,
            ..Default::default()
        }
    }

    /// Whether the candidates may miss a contact. A pair left out was farther than
    /// r + skin at the coarse detection; since then the particle has moved at most
    /// `displacement` (its largest distance from the DEM list's build positions) plus
    /// `offset`, and the edge at most as far as its farther node: the list holds while
    /// the two add up to at most the skin.
    pub fn stale(&self, c: &Charge, displacement: f64) -> bool {
        if self.nodes_at_build.len() != c.boundary.len() {
            return true;
        }
        let nodes = c
            .boundary
            .iter()
            .zip(&self.nodes_at_build)
            .map(|(e, x0)| (c.nodes.pos[e[0] as usize] - *x0).length_squared())
            .fold(0.0, f64::max)
            .sqrt();
        displacement + self.offset + nodes > self.skin
    }

    /// [`Coupling::rebuild`] made when the particles are up to `displacement` from the
    /// DEM list's build positions.
    pub fn rebuild_at(&mut self, c: &Charge, p: &Particles, displacement: f64) {
        self.rebuild(c, p);
        self.offset = displacement;
    }

    /// Coarse detection: lists the (particle, edge) pairs within r + skin.
    pub fn rebuild(&mut self, c: &Charge, p: &Particles) {
        let edges: Vec<(DVec2, DVec2)> = c
            .boundary
            .iter()
            .map(|e| (c.nodes.pos[e[0] as usize], c.nodes.pos[e[1] as usize]))
            .collect();
        self.nodes_at_build = c
            .boundary
            .iter()
            .map(|e| c.nodes.pos[e[0] as usize])
            .collect();
        if self.apex.len() != c.boundary.len() {
            self.apex = apexes(c);
        }
        self.builds += 1;
        let reach = p.max_radius() + self.skin;
        let grid = EdgeGrid::new(&edges, reach);
        let skin = self.skin;
        let parts: Vec<Vec<(u32, u32)>> = p
            .pos
            .par_chunks(CHUNK)
            .enumerate()
            .map(|(ci, xs)| {
                let mut out = Vec::new();
                for (k, &x) in xs.iter().enumerate() {
                    let i = ci * CHUNK + k;
                    let Some(cell) = grid.cell_of(x) else {
                        continue;
                    };
                    for &e in grid.edges_in(cell) {
                        let (a, b) = edges[e as usize];
                        if segment_distance(x, a, b) <= p.radius[i] + skin {
                            out.push((i as u32, e));
                        }
                    }
                }
                out
            })
            .collect();
        self.candidates = parts.concat();
    }

    /// The stable step of the penalty springs as they are now (infinity with no
    /// contact). A boundary node carries every grain on its two edges, and the edges
    /// lengthen several-fold as the products expand, so a node comes to hold many
    /// springs at once: its frequency grows with their number, which the single-contact
    /// estimate made before the run cannot see. The bound is Gershgorin's on the
    /// mass-normalised stiffness of the springs (each row: Σ K·|w_r w_c|/√(m_r m_c)).
    pub fn stable_dt(&self) -> f64 {
        if self.omega2_max > 0.0 {
            2.0 / self.omega2_max.sqrt()
        } else {
            f64::INFINITY
        }
    }

    /// Fine detection and forces: adds the penalty force to `p.force` and sets the
    /// charge's external nodal forces to the reactions.
    ///
    /// K_pe is the stiffness of a grain on the charge's edge as meshed. As the products
    /// expand, the boundary edges lengthen several-fold and a node comes to carry many
    /// grains: at a fixed K_pe per grain its springs add up and its stable step shrinks
    /// (test 2: from 2.27 to 0.83 ns). So each node may carry springs over at most the
    /// length of edge it had at the start, `l0` (the mean of its two edges' initial
    /// lengths): the grains on it cover `c` = Σ w·d (w the node's share of a grain's
    /// reaction, d the grain's diameter), and their springs get K_pe·min(1, l0/c). On
    /// an edge covered end to end, c is the edge's length l, and this is K_pe·l0/l. A
    /// few grains on a long edge (the tip of a finger of gas between grains, whose
    /// edges stretch a hundred-fold) keep the full K_pe, which the edge's length alone
    /// would have softened until a fast node drove through them.
    pub fn forces(&mut self, c: &mut Charge, p: &mut Particles) {
        self.forces_on(c, p, &Serial);
    }

    /// [`Coupling::forces`] on one rank of several: `comm` tells which particles are
    /// this rank's own (a ghost's contacts are its owner's) and gathers every rank's
    /// contacts, so that every sum over them (the charge's nodal forces, the cover,
    /// the energy, the frequency bound) is taken in one order of (grain id, edge) and
    /// is the same on every rank ([`crate::hits`]); the penalty force goes to the
    /// grains this rank owns.
    pub fn forces_on(&mut self, c: &mut Charge, p: &mut Particles, comm: &dyn Exchange) {
        for f in c.nodes.f_ext.iter_mut() {
            *f = DVec2::ZERO;
        }
        let nodes = c.nodes.pos.len();
        self.node_row.clear();
        self.node_row.resize(nodes, 0.0);
        self.cover.clear();
        self.cover.resize(nodes, 0.0);
        let (mut row_owner, mut particle_row, mut particle_max) = (None, 0.0f64, 0.0f64);
        self.contacts = 0;
        self.max_penetration_ratio = 0.0;
        self.deepest = None;
        self.energy = 0.0;
        self.radial_force = 0.0;
        let nb_edges = c.boundary.len();
        if self.node_length.len() != nodes {
            self.node_length = vec![0.0; nodes];
            for e in &c.boundary {
                let l = (c.nodes.pos[e[1] as usize] - c.nodes.pos[e[0] as usize]).length();
                self.node_length[e[0] as usize] += 0.5 * l;
                self.node_length[e[1] as usize] += 0.5 * l;
            }
        }
        // Fine detection of this rank's own grains.
        let mut own = std::mem::take(&mut self.hits);
        own.clear();
        for &(i, e) in &self.candidates {
            let (iu, eu) = (i as usize, e as usize);
            if !comm.owns(iu) {
                continue;
            }
            let [na, nb] = c.boundary[eu];
            let (a, b) = (c.nodes.pos[na as usize], c.nodes.pos[nb as usize]);
            let (x, r) = (p.pos[iu], p.radius[iu]);
            let apex = c.nodes.pos[self.apex[eu] as usize];
            let (touch, corner) = match touch(x, r, a, b, apex) {
                Some(h) => (h, false),
                None => {
                    // The edge's first node, where the edge before it ends.
                    let before = c.boundary[(eu + nb_edges - 1) % nb_edges][0];
                    match corner(x, r, c.nodes.pos[before as usize], a, b) {
                        Some(h) => (h, true),
                        None => continue,
                    }
                }
            };
            own.push(Hit {
                id: p.id[iu],
                edge: e,
                touch,
                corner,
                radius: r,
                mass: p.mass(iu),
                pos: x,
                local: Some(i),
            });
        }
        self.hits = hits::canonical(own, comm);
        // The length of edge each node's grains cover.
        for h in &self.hits {
            let [na, nb] = c.boundary[h.edge as usize];
            let d = 2.0 * h.radius;
            self.cover[na as usize] += (1.0 - h.touch.at) * d;
            self.cover[nb as usize] += h.touch.at * d;
        }
        for h in &self.hits {
            let (hit, e) = (h.touch, h.edge as usize);
            let [na, nb] = c.boundary[e];
            let (na, nb) = (na as usize, nb as usize);
            let mut ratio: f64 = 1.0;
            for (n, w) in [(na, 1.0 - hit.at), (nb, hit.at)] {
                if w > 0.0 {
                    ratio = ratio.min(self.node_length[n] / self.cover[n]);
                }
            }
            let k = self.stiffness * ratio;
            let f = k * hit.overlap * hit.normal;
            if let Some(i) = h.local {
                p.force[i as usize] += f;
            }
            c.nodes.f_ext[na] -= (1.0 - hit.at) * f;
            c.nodes.f_ext[nb] -= hit.at * f;
            // The spring couples the particle (weight 1) and the two nodes (weights
            // 1 − at and at): add |K w_r w_c|/√(m_r m_c) to each of the three rows.
            let (ma, mb, mp) = (c.nodes.mass[na], c.nodes.mass[nb], h.mass);
            let (wa, wb) = ((1.0 - hit.at).abs(), hit.at.abs());
            let (sa, sb, sp) = (wa / ma.sqrt(), wb / mb.sqrt(), 1.0 / mp.sqrt());
            let sum = sa + sb + sp;
            self.node_row[na] += k * sa * sum;
            self.node_row[nb] += k * sb * sum;
            if row_owner != Some(h.id) {
                particle_max = particle_max.max(particle_row);
                (row_owner, particle_row) = (Some(h.id), 0.0);
            }
            particle_row += k * sp * sum;
            self.contacts += 1;
            let r = h.radius;
            if hit.overlap / r > self.max_penetration_ratio {
                self.max_penetration_ratio = hit.overlap / r;
                let (a, b) = (c.nodes.pos[na], c.nodes.pos[nb]);
                let l0 = self.node_length[na] + self.node_length[nb];
                self.deepest = Some(Deepest {
                    id: h.id,
                    pos: h.pos,
                    edge: e,
                    touch: hit,
                    corner: h.corner,
                    stretch: (b - a).length() / l0.max(f64::MIN_POSITIVE) * 2.0,
                    stiffness: k,
                });
            }
            self.energy += 0.5 * k * hit.overlap * hit.overlap;
            self.radial_force += f.length();
        }
        particle_max = particle_max.max(particle_row);
        let node_max = self.node_row.iter().copied().fold(0.0, f64::max);
        self.omega2_max = node_max.max(particle_max);
    }
}

/// The deepest contact of an evaluation: what a diagnostic needs to say where and why.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Deepest {
    /// The grain's global id.
    pub id: u32,
    /// The grain's centre (m).
    pub pos: DVec2,
    /// Boundary edge index.
    pub edge: usize,
    /// The contact.
    pub touch: Touch,
    /// Whether it is the corner contact (node, not edge).
    pub corner: bool,
    /// The edge's length over the mean initial length of its nodes' edges.
    pub stretch: f64,
    /// The spring's stiffness (N/m).
    pub stiffness: f64,
}

/// A particle touching an edge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Touch {
    /// Outward unit normal of the edge.
    pub normal: DVec2,
    /// Overlap r − d (m), d the signed distance of the centre from the edge line.
    pub overlap: f64,
    /// Position of the projection along the edge, 0 at its first node, 1 at its second.
    pub at: f64,
}

/// Eq. C1 for a particle at `x` of radius `r` and the boundary edge a → b (the charge
/// on its left), whose triangle's third node is `apex`. A centre on the charge's side
/// of the edge line counts only while it lies inside that triangle: a grain beside a
/// thin finger of gas must not be pushed through the finger by the finger's far edge.
#[inline]
pub fn touch(x: DVec2, r: f64, a: DVec2, b: DVec2, apex: DVec2) -> Option<Touch> {
    let t = b - a;
    let len = t.length();
    if len == 0.0 {
        return None;
    }
    let tau = t / len;
    let rel = x - a;
    let s = rel.dot(tau);
    if !(0.0..=len).contains(&s) {
        return None;
    }
    let normal = DVec2::new(tau.y, -tau.x);
    let d = rel.dot(normal);
    if d >= r || d <= -r {
        return None;
    }
    if d < 0.0 {
        let inside = (apex - b).perp_dot(x - b) >= 0.0 && (a - apex).perp_dot(x - apex) >= 0.0;
        if !inside {
            return None;
        }
    }
    Some(Touch {
        normal,
        overlap: r - d,
        at: s / len,
    })
}

/// Contact with the node `a` shared by the edges p → a and a → b, for a centre in the
/// wedge outside a convex corner, where it projects inside neither edge: Eq. C1 alone
/// would let a grain sink onto the node there. The normal runs from the node to the
/// centre and the whole reaction goes to the node (`at` = 0).
#[inline]
pub fn corner(x: DVec2, r: f64, p: DVec2, a: DVec2, b: DVec2) -> Option<Touch> {
    let (tp, te) = (a - p, b - a);
    if tp.perp_dot(te) <= 0.0 {
        return None; // reflex (or straight) corner: the edges' own contacts cover it
    }
    let rel = x - a;
    if rel.dot(te) >= 0.0 || rel.dot(tp) <= 0.0 {
        return None; // projects inside one of the edges
    }
    let d = rel.length();
    if d >= r || d == 0.0 {
        return None;
    }
    Some(Touch {
        normal: rel / d,
        overlap: r - d,
        at: 0.0,
    })
}

/// For each boundary edge, the third node of the one triangle that has it.
fn apexes(c: &Charge) -> Vec<u32> {
    let mut by_edge = std::collections::HashMap::new();
    for t in &c.elems.tri {
        for k in 0..3 {
            by_edge.insert((t[k], t[(k + 1) % 3]), t[(k + 2) % 3]);
        }
    }
    c.boundary.iter().map(|e| by_edge[&(e[0], e[1])]).collect()
}

fn segment_distance(x: DVec2, a: DVec2, b: DVec2) -> f64 {
    let t = b - a;
    let l2 = t.length_squared();
    let s = if l2 > 0.0 {
        ((x - a).dot(t) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + s * t - x).length()
}

/// Uniform grid over the boundary's bounding box (grown by the reach), each cell
/// listing the edges whose box, grown by the reach, overlaps it.
struct EdgeGrid {
    lo: DVec2,
    inv_h: f64,
    n: [usize; 2],
    start: Vec<u32>,
    items: Vec<u32>,
}

impl EdgeGrid {
    fn new(edges: &[(DVec2, DVec2)], reach: f64) -> Self {
        let mut lo = DVec2::INFINITY;
        let mut hi = DVec2::NEG_INFINITY;
        for &(a, b) in edges {
            lo = lo.min(a).min(b);
            hi = hi.max(a).max(b);
        }
        lo -= DVec2::splat(reach);
        hi += DVec2::splat(reach);
        // Cells as wide as a typical edge, not the longest: an edge is listed in every
        // cell its box overlaps, so any width finds the same candidates, and as the
        // products expand a few edges stretch to the size of the whole charge (test 2:
        // 101 mm at 100 µs against a median of 0.8 mm), which would leave one cell
        // holding every edge for every grain to test.
        let mut lengths: Vec<f64> = edges.iter().map(|&(a, b)| (b - a).length()).collect();
        let typical = if lengths.is_empty() {
            0.0
        } else {
            let mid = lengths.len() / 2;
            *lengths.select_nth_unstable_by(mid, f64::total_cmp).1
        };
        let mut h = (typical + 2.0 * reach).max(1e-12);
        // Bound the cell count (and memory) by a few cells per edge.
        let max_cells = (16 * edges.len()).max(1024) as f64;
        let want = ((hi.x - lo.x) / h).ceil() * ((hi.y - lo.y) / h).ceil();
        if want > max_cells {
            h *= (want / max_cells).sqrt();
        }
        let n = [
            (((hi.x - lo.x) / h).ceil() as usize).max(1),
            (((hi.y - lo.y) / h).ceil() as usize).max(1),
        ];
        let inv_h = 1.0 / h;
        let cells_of = |a: DVec2, b: DVec2| {
            let l = (a.min(b) - DVec2::splat(reach) - lo) * inv_h;
            let u = (a.max(b) + DVec2::splat(reach) - lo) * inv_h;
            let c = |v: f64, m: usize| (v.floor().max(0.0) as usize).min(m - 1);
            (c(l.x, n[0])..=c(u.x, n[0]), c(l.y, n[1])..=c(u.y, n[1]))
        };
        let mut count = vec![0u32; n[0] * n[1] + 1];
        for &(a, b) in edges {
            let (xs, ys) = cells_of(a, b);
            for y in ys {
                for x in xs.clone() {
                    count[y * n[0] + x + 1] += 1;
                }
            }
        }
        for k in 0..n[0] * n[1] {
            count[k + 1] += count[k];
        }
        let mut fill = count.clone();
        let mut items = vec![0u32; count[n[0] * n[1]] as usize];
        for (e, &(a, b)) in edges.iter().enumerate() {
            let (xs, ys) = cells_of(a, b);
            for y in ys {
                for x in xs.clone() {
                    let slot = &mut fill[y * n[0] + x];
                    items[*slot as usize] = e as u32;
                    *slot += 1;
                }
            }
        }
        EdgeGrid {
            lo,
            inv_h,
            n,
            start: count,
            items,
        }
    }

    fn cell_of(&self, x: DVec2) -> Option<usize> {
        let c = (x - self.lo) * self.inv_h;
        if c.x < 0.0 || c.y < 0.0 {
            return None;
        }
        let (cx, cy) = (c.x as usize, c.y as usize);
        (cx < self.n[0] && cy < self.n[1]).then_some(cy * self.n[0] + cx)
    }

    fn edges_in(&self, cell: usize) -> &[u32] {
        &self.items[self.start[cell] as usize..self.start[cell + 1] as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn touch_follows_eq_c1() {
        // Edge along +x: the charge lies above it (on its left), outward is −y.
        let (a, b, apex) = (DVec2::ZERO, DVec2::new(1.0, 0.0), DVec2::new(0.5, 0.5));
        let t = touch(DVec2::new(0.25, -0.08), 0.1, a, b, apex).unwrap();
        assert!((t.normal - DVec2::new(0.0, -1.0)).length() < 1e-15);
        assert!((t.overlap - 0.02).abs() < 1e-12);
        assert!((t.at - 0.25).abs() < 1e-12);
        // Too far, or projecting outside the edge: no contact.
        assert!(touch(DVec2::new(0.25, -0.2), 0.1, a, b, apex).is_none());
        assert!(touch(DVec2::new(1.05, -0.05), 0.1, a, b, apex).is_none());
        // A corner: the wedge outside it touches the node, the edge contacts do not.
        let (p, b2) = (DVec2::new(-1.0, 1.0), DVec2::new(1.0, 1.0));
        let a0 = DVec2::ZERO;
        // Path p → a0 → b2 turns left (a convex corner, charge above): the wedge is below a0.
        let t = corner(DVec2::new(0.0, -0.05), 0.1, p, a0, b2).unwrap();
        assert!((t.normal - DVec2::new(0.0, -1.0)).length() < 1e-12);
        assert!((t.overlap - 0.05).abs() < 1e-12);
        assert!(corner(DVec2::new(0.3, -0.05), 0.1, p, a0, b2).is_none());
        // A centre pushed just past the edge, into its triangle, still gets pushed out;
        // one beyond a thin triangle (a finger of gas) does not get pulled through it.
        let t = touch(DVec2::new(0.5, 0.03), 0.1, a, b, apex).unwrap();
        assert!((t.overlap - 0.13).abs() < 1e-12);
        let thin = DVec2::new(0.5, 0.02);
        assert!(touch(DVec2::new(0.5, 0.05), 0.1, a, b, thin).is_none());
    }
}
