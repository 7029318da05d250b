//! Grid storage. Each body has its own *patch*: a rectangle of nodes just covering its
//! points, stored column-major so that a strip of columns is one contiguous slice. Bodies
//! that may touch also sum into one *global* grid (total mass, momentum, mass gradient,
//! the rigid share, and the two heaviest bodies per node), which is all a body's contact
//! correction needs: the cost is linear in the number of bodies, never in pairs.

use crate::grid::{Grid, Rows};
use glam::DVec2;
use rayon::prelude::*;

/// One body's fields at one node. Kept as one 64-byte record because the scatter
/// updates all of them together.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct Node {
    /// Mass.
    pub m: f64,
    /// Momentum.
    pub p: DVec2,
    /// Force (internal + gravity, plus contact impulse / Δt after the second pass).
    pub f: DVec2,
    /// Mass gradient Σ m_p ∇S_ip (outward normal direction of the body).
    pub g: DVec2,
    /// Corrections applied here this step: bit 0 body contact, bits 1–4 walls
    /// (left, right, bottom, top).
    pub touched: u32,
}

/// Velocities read back by the particles.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Kin {
    /// Grid velocity (after integration and contact, or as used for the strain rate).
    pub v: DVec2,
    /// Acceleration seen by FLIP.
    pub a: DVec2,
}

/// What a bonded interface needs at one node of one body: Σ S m σ (for the normal
/// traction of the stresses), the strongest bond among the points that reach the node,
/// the normal force the intact bond carries and the interface length the node stands for,
/// and whether the bond failed here this step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BondNode {
    /// Σ S m (σ_xx, σ_yy, σ_xy).
    pub ms: [f64; 3],
    /// Largest bond strength of the points with weight here (Pa).
    pub strength: f64,
    /// Normal force (tension > 0, N per unit thickness) the intact bond must carry.
    pub force: f64,
    /// Interface length the node stands for (m).
    pub length: f64,
    /// The bond failed at this node this step: its points lose their bond.
    pub failed: bool,
}

/// One body's nodes.
#[derive(Clone, Debug, Default)]
pub struct Patch {
    /// First stored node (column, row).
    pub lo: [usize; 2],
    /// Columns and rows.
    pub size: [usize; 2],
    /// Node fields, column-major.
    pub nodes: Vec<Node>,
    /// Kinematics, same indexing.
    pub kin: Vec<Kin>,
    /// Σ S m x: with the mass, where the body's material near the node is centred (only
    /// kept when contact uses the separation test; empty otherwise).
    pub xs: Vec<DVec2>,
    /// Bonded-interface sums (only kept when some contact law bonds; empty otherwise).
    pub bond: Vec<BondNode>,
    /// What the energy ledger needs of each node ([`crate::Setup::ledger`]; empty
    /// otherwise).
    pub ledger: Vec<LedgerNode>,
}

/// One node's share of the energy ledger in a step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LedgerNode {
    /// The velocity the counted contact corrections gave the node, by pass (the first,
    /// after the transfer; the second, after integration) and by kind
    /// ([`crate::contact::SLIDE`], [`crate::contact::HELD`]).
    pub dv: [[DVec2; 2]; 2],
    /// The internal and body force integrated in the step (before the second pass).
    pub f: DVec2,
}

impl Patch {
    /// Re-shapes the patch to cover stored nodes `[lo, hi)` and zeroes it; keeps the
    /// centroid sums if `positions`, the bond sums if `bonds` and the contact velocity
    /// changes if `ledger`.
    pub fn reset(
        &mut self,
        lo: [usize; 2],
        hi: [usize; 2],
        positions: bool,
        bonds: bool,
        ledger: bool,
    ) {
        self.lo = lo;
        self.size = [hi[0] - lo[0], hi[1] - lo[1]];
        let n = self.size[0] * self.size[1];
        self.nodes.clear();
        self.nodes.resize(n, Node::default());
        self.kin.clear();
        self.kin.resize(n, Kin::default());
        self.xs.clear();
        if positions {
            self.xs.resize(n, DVec2::ZERO);
        }
        self.bond.clear();
        if bonds {
            self.bond.resize(n, BondNode::default());
        }
        self.ledger.clear();
        if ledger {
            self.ledger.resize(n, LedgerNode::default());
        }
    }

    /// Records the momentum change `dp` of a correction of kind `kind` in pass `pass`
    /// (0 or 1) at local node `k`, as a velocity change (only with the ledger kept).
    #[inline]
    pub fn record(&mut self, k: usize, pass: usize, kind: usize, dp: DVec2) {
        if !self.ledger.is_empty() {
            self.ledger[k].dv[pass][kind] += dp / self.nodes[k].m;
        }
    }

    /// Stored (column, row) of local index `k`.
    #[inline]
    pub fn stored(&self, k: usize) -> [usize; 2] {
        [self.lo[0] + k / self.size[1], self.lo[1] + k % self.size[1]]
    }

    /// Stored column range `[lo, hi)`.
    pub fn columns(&self) -> (usize, usize) {
        (self.lo[0], self.lo[0] + self.size[0])
    }

    /// Local (image, canonical) row pairs of a periodic y where both rows lie in the
    /// patch: the patch of a body that straddles the seam (or spans the period) holds
    /// one node twice.
    fn images(&self, rows: Rows) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        let (r0, n) = (self.lo[1], self.size[1]);
        (0..n).filter_map(move |i| {
            let c = rows.canonical(r0 + i);
            (c != r0 + i && (r0..r0 + n).contains(&c)).then(|| (i, c - r0, rows.shift(r0 + i)))
        })
    }

    /// Along a periodic y, adds what a scatter put on each image row to its canonical row
    /// (positions moved by the period) and empties the image, so every later stage sees
    /// one node; a no-op for a patch that does not hold a node twice. `h` is the cell size.
    pub fn fold(&mut self, rows: Rows, h: f64) {
        let n = self.size[1];
        let pairs: Vec<(usize, usize, f64)> = self.images(rows).collect();
        for col in 0..self.size[0] {
            for &(i, j, shift) in &pairs {
                let (a, b) = (col * n + i, col * n + j);
                let src = std::mem::take(&mut self.nodes[a]);
                let dst = &mut self.nodes[b];
                dst.m += src.m;
                dst.p += src.p;
                dst.f += src.f;
                dst.g += src.g;
                dst.touched |= src.touched;
                if !self.xs.is_empty() {
                    let x = std::mem::take(&mut self.xs[a]);
                    self.xs[b] += x + DVec2::new(0.0, src.m * shift * h);
                }
                if !self.bond.is_empty() {
                    let src = std::mem::take(&mut self.bond[a]);
                    let dst = &mut self.bond[b];
                    for c in 0..3 {
                        dst.ms[c] += src.ms[c];
                    }
                    dst.strength = dst.strength.max(src.strength);
                    dst.failed |= src.failed;
                }
            }
        }
    }

    /// Along a periodic y, copies each canonical row's kinematics (and bond failures)
    /// to its image in the patch, for the points that read the image.
    pub fn unfold(&mut self, rows: Rows) {
        let n = self.size[1];
        let pairs: Vec<(usize, usize, f64)> = self.images(rows).collect();
        for col in 0..self.size[0] {
            for &(i, j, _) in &pairs {
                self.kin[col * n + i] = self.kin[col * n + j];
                if !self.bond.is_empty() {
                    self.bond[col * n + i].failed = self.bond[col * n + j].failed;
                }
            }
        }
    }

    /// Σ S m x at local node `k`, seen from the canonical row (the position sum of an
    /// image row moved by the period); zero when positions are not kept.
    #[inline]
    pub fn position_sum(&self, k: usize, rows: Option<Rows>, h: f64) -> DVec2 {
        let x = self.xs[k];
        match rows {
            None => x,
            Some(w) => {
                let shift = w.shift(self.lo[1] + k % self.size[1]);
                x + DVec2::new(0.0, self.nodes[k].m * shift * h)
            }
        }
    }
}

/// The sum over bodies at one node.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GlobalNode {
    /// Total mass.
    pub m: f64,
    /// Total momentum.
    pub p: DVec2,
    /// Total mass gradient.
    pub g: DVec2,
    /// Mass of rigid (prescribed) bodies.
    pub m_rigid: f64,
    /// Momentum of rigid bodies.
    pub p_rigid: DVec2,
    /// Mass gradient of rigid bodies.
    pub g_rigid: DVec2,
    /// Σ S m x of all bodies (when positions are kept).
    pub x: DVec2,
    /// Σ S m x of rigid bodies.
    pub x_rigid: DVec2,
    /// Bodies with mass here.
    pub count: u32,
    /// Heaviest body here, and the second heaviest.
    pub top: [u16; 2],
    /// Their masses.
    pub top_m: [f64; 2],
}

impl GlobalNode {
    /// The heaviest body here other than `b`: the partner whose contact law applies.
    #[inline]
    pub fn partner(&self, b: u16) -> u16 {
        if self.top[0] == b {
            self.top[1]
        } else {
            self.top[0]
        }
    }
}

/// The sum over bodies of [`BondNode`] at one node.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GlobalBond {
    /// Σ S m σ over all bodies.
    pub ms: [f64; 3],
    /// Largest bond of any point reaching the node.
    pub strength: f64,
    /// Σ normal force over bodies.
    pub force: f64,
    /// Σ interface length over bodies.
    pub length: f64,
    /// The normal traction of the intact bond, smoothed along the interface
    /// ([`crate::bond::smooth`]).
    pub traction: f64,
}

/// The whole grid's sums, column-major over stored nodes. Along a periodic y, a patch's
/// image rows add to their canonical rows; the image rows of the global grid stay empty.
#[derive(Clone, Debug, Default)]
pub struct Global {
    /// Stored nodes along x and y.
    pub dims: [usize; 2],
    /// Row arithmetic of a periodic y.
    pub wrap: Option<Rows>,
    /// Cell size (m), to move image positions by the period.
    pub h: f64,
    /// Node sums.
    pub nodes: Vec<GlobalNode>,
    /// Bonded-interface sums, same indexing (empty when no law bonds).
    pub bond: Vec<GlobalBond>,
}

/// Columns per parallel band when summing patches.
const BAND: usize = 16;

/// Adds body `b`'s node `n` (position sum `x`) to the sums `g`.
#[inline(always)]
fn add_node(g: &mut GlobalNode, n: &Node, x: DVec2, b: u16, rigid: bool) {
    g.m += n.m;
    g.p += n.p;
    g.g += n.g;
    g.count += 1;
    g.x += x;
    if rigid {
        g.m_rigid += n.m;
        g.p_rigid += n.p;
        g.g_rigid += n.g;
        g.x_rigid += x;
    }
    if g.count == 1 || n.m > g.top_m[0] {
        g.top = [b, g.top[0]];
        g.top_m = [n.m, g.top_m[0]];
    } else if g.count == 2 || n.m > g.top_m[1] {
        g.top[1] = b;
        g.top_m[1] = n.m;
    }
}

impl Global {
    /// Sized for `grid`, zeroed; with the bond sums if `bonds`.
    pub fn new(grid: &Grid, bonds: bool) -> Self {
        let dims = grid.stored();
        let n = dims[0] * dims[1];
        Global {
            dims,
            wrap: grid.canonical_rows(),
            h: grid.h,
            nodes: vec![GlobalNode::default(); n],
            bond: if bonds {
                vec![GlobalBond::default(); n]
            } else {
                Vec::new()
            },
        }
    }

    /// Sums every patch into the grid: masses, momenta and gradients, or (`momentum_only`)
    /// just the momenta after they changed. Bodies are added in index order, so the sums
    /// do not depend on the thread count.
    pub fn accumulate(&mut self, patches: &[Patch], rigid: &[bool], momentum_only: bool) {
        let rows = self.dims[1];
        let (wrap, h) = (self.wrap, self.h);
        if !momentum_only && !self.bond.is_empty() {
            self.accumulate_bonds(patches, false);
        }
        self.nodes
            .par_chunks_mut(BAND * rows)
            .enumerate()
            .for_each(|(band, chunk)| {
                let c0 = band * BAND;
                let c1 = c0 + chunk.len() / rows;
                if momentum_only {
                    chunk.iter_mut().for_each(|g| g.p = g.p_rigid);
                } else {
                    chunk.fill(GlobalNode::default());
                }
                for (b, patch) in patches.iter().enumerate() {
                    let (p0, p1) = patch.columns();
                    let (a, z) = (c0.max(p0), c1.min(p1));
                    let keep = !patch.xs.is_empty();
                    let add = |g: &mut GlobalNode, n: &Node, k: usize| {
                        if momentum_only {
                            if !rigid[b] {
                                g.p += n.p;
                            }
                            return;
                        }
                        let x = if keep {
                            patch.position_sum(k, wrap, h)
                        } else {
                            DVec2::ZERO
                        };
                        add_node(g, n, x, b as u16, rigid[b]);
                    };
                    for col in a..z {
                        let at = (col - p0) * patch.size[1];
                        let src = &patch.nodes[at..][..patch.size[1]];
                        let dst = &mut chunk[(col - c0) * rows..][..rows];
                        match wrap {
                            None => {
                                let dst = &mut dst[patch.lo[1]..][..patch.size[1]];
                                for (r, (g, n)) in dst.iter_mut().zip(src).enumerate() {
                                    if n.m > 0.0 {
                                        add(g, n, at + r);
                                    }
                                }
                            }
                            Some(w) => {
                                for (r, n) in src.iter().enumerate() {
                                    if n.m > 0.0 {
                                        add(&mut dst[w.canonical(patch.lo[1] + r)], n, at + r);
                                    }
                                }
                            }
                        }
                    }
                }
            });
    }

    /// Sums the patches' bond records (bodies in index order): the stress sums and
    /// strengths, or (`forces`) only the forces and lengths.
    pub fn accumulate_bonds(&mut self, patches: &[Patch], forces: bool) {
        let rows = self.dims[1];
        let wrap = self.wrap;
        self.bond
            .par_chunks_mut(BAND * rows)
            .enumerate()
            .for_each(|(band, chunk)| {
                let c0 = band * BAND;
                let c1 = c0 + chunk.len() / rows;
                for g in chunk.iter_mut() {
                    if forces {
                        (g.force, g.length) = (0.0, 0.0);
                    } else {
                        *g = GlobalBond::default();
                    }
                }
                let add = |g: &mut GlobalBond, n: &BondNode| {
                    if forces {
                        g.force += n.force;
                        g.length += n.length;
                        return;
                    }
                    for c in 0..3 {
                        g.ms[c] += n.ms[c];
                    }
                    g.strength = g.strength.max(n.strength);
                };
                for patch in patches.iter().filter(|p| !p.bond.is_empty()) {
                    let (p0, p1) = patch.columns();
                    for col in c0.max(p0)..c1.min(p1) {
                        let src = &patch.bond[(col - p0) * patch.size[1]..][..patch.size[1]];
                        let dst = &mut chunk[(col - c0) * rows..][..rows];
                        match wrap {
                            None => {
                                let dst = &mut dst[patch.lo[1]..][..patch.size[1]];
                                for (g, n) in dst.iter_mut().zip(src) {
                                    add(g, n);
                                }
                            }
                            Some(w) => {
                                for (r, n) in src.iter().enumerate() {
                                    add(&mut dst[w.canonical(patch.lo[1] + r)], n);
                                }
                            }
                        }
                    }
                }
            });
    }

    /// Global index of a stored node (its canonical row along a periodic y).
    #[inline]
    pub fn index(&self, col: usize, row: usize) -> usize {
        col * self.dims[1] + self.wrap.map_or(row, |w| w.canonical(row))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sums_and_partners() {
        let grid = Grid {
            lo: DVec2::ZERO,
            h: 1.0,
            cells: [40, 3],
            periodic_y: false,
        };
        let mut patches = vec![Patch::default(), Patch::default(), Patch::default()];
        patches[0].reset([2, 1], [20, 4], false, false, false);
        patches[1].reset([18, 0], [30, 3], false, false, false);
        patches[2].reset([19, 1], [21, 2], false, false, false);
        for (b, p) in patches.iter_mut().enumerate() {
            for n in &mut p.nodes {
                n.m = 1.0 + b as f64;
                n.p = DVec2::new(b as f64, 1.0);
            }
        }
        let mut g = Global::new(&grid, false);
        g.accumulate(&patches, &[false, false, true], false);
        let at = g.nodes[g.index(19, 1)];
        assert_eq!(at.count, 3);
        assert_eq!(at.m, 6.0);
        assert_eq!(at.m_rigid, 3.0);
        assert_eq!(at.top, [2, 1]);
        assert_eq!(at.partner(2), 1);
        assert_eq!(at.partner(0), 2);
        assert_eq!(g.nodes[g.index(5, 2)].count, 1);
        // Momentum-only refresh keeps the rigid share and re-adds the rest.
        patches[0].nodes.iter_mut().for_each(|n| n.p = DVec2::ZERO);
        g.accumulate(&patches, &[false, false, true], true);
        let at = g.nodes[g.index(19, 1)];
        assert_eq!(at.p, DVec2::new(1.0 + 2.0, 2.0));
    }
}
