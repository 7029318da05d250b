//! Contact on the grid (Bardenhagen et al. 1998/2000, in NairnMPM's momentum form):
//! each body's nodal momentum is moved toward the centre-of-mass momentum of all bodies
//! at that node, wholly in the normal direction when approaching and, tangentially, up to
//! Coulomb's μ times the normal change. The normal of body b is colinear with the other
//! bodies' (n_b ∝ g_b − g_rest), so two bodies get equal and opposite corrections and
//! momentum is conserved. Rigid bodies take the place of the centre of mass, and their
//! mass gradient gives the normal. Here each free body corrects its own patch at the nodes
//! it shares with one other free body; nodes where more meet, or a rigid body meets
//! another, are resolved pair by pair in [`crate::crowd`] (unless the lumped rule is
//! asked for). The domain edges are walls with exact normals and the same law. Bonded
//! pairs follow [`crate::bond`].

use crate::bond;
use crate::grid::{Grid, Rows, GHOST};
use crate::nodes::{GlobalBond, GlobalNode, Node, Patch};
use crate::setup::{ContactLaw, ContactTable};
use crate::shape::{Bspline2, Gimp, Kernel, Linear, ShapeFunction};
use glam::DVec2;

/// Which of the two corrections of a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pass {
    /// On the interpolated momenta (and MUSL's re-mapped ones): momentum only.
    Interpolated = 0,
    /// After integration: the change also enters the nodal force, so FLIP sees it.
    Integrated = 1,
}

/// The Coulomb-limited momentum change that brings `dp` (stick change) into contact
/// along the unit normal `n`; `None` if the fields separate. `mu = None`: no slip.
#[inline]
pub fn coulomb(dp: DVec2, n: DVec2, law: ContactLaw) -> Option<DVec2> {
    match law {
        ContactLaw::NoSlip => Some(dp),
        ContactLaw::Coulomb { mu } | ContactLaw::Bonded { mu, .. } => {
            let dn = dp.dot(n);
            if dn >= 0.0 {
                return None;
            }
            let t = dp - dn * n;
            let ts = t.length();
            let cap = -mu * dn;
            Some(if ts > cap {
                dn * n + t * (cap / ts)
            } else {
                dp
            })
        }
    }
}

/// What a body's corrections touched and exchanged in a pass (or a step, merged). The
/// momenta and works count only the corrections that reach the particles (the second
/// pass, and the first with `pass1_to_particles`), so over a step they are what the
/// points receive.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Touch {
    /// Nodes corrected against other bodies.
    pub body_nodes: u32,
    /// Heaviest partner at the last such node.
    pub partner: Option<u16>,
    /// Walls touched: bit k for side k (left, right, bottom, top).
    pub walls: u8,
    /// Nodes where a bond failed.
    pub debonded: u32,
    /// Momentum this body's field received from free bodies' fields (N·s per unit
    /// thickness).
    pub from_free: DVec2,
    /// Momentum received from rigid bodies; for a rigid body, the momentum it received
    /// from the free bodies (the reaction to what it gave them).
    pub from_rigid: DVec2,
    /// Momentum received from the walls.
    pub from_walls: DVec2,
    /// Work of rigid bodies through these corrections, by kind ([`SLIDE`], [`HELD`]): a
    /// rigid body's on the free bodies' fields (and, under the lumped rule, a rigid
    /// master's on this free body's field); J per unit thickness.
    pub work: [f64; 2],
    /// With [`crate::Setup::ledger`], over the velocity change the particles take from
    /// the grid, at its midpoint velocity v̄: the work Σ m v̄·δv of this body's
    /// corrections of each kind on its grid field (δv the velocity they gave a node) ...
    pub grid: [f64; 2],
    /// ... and its grid field's kinetic energy change Σ m v̄·Δv, of which they are part
    /// (the rest is the internal and body forces' work).
    pub ke_grid: f64,
    /// Its points' kinetic energy change. ke_grid − ke_points ≥ 0 is what the transfer
    /// to the points loses (the FLIP projection of a non-smooth change).
    pub ke_points: f64,
}

/// Kind of a correction: Coulomb friction (sliding, sticking or approaching), walls.
pub const SLIDE: usize = 0;
/// Kind of a correction: an intact (or failing) bond or `no_slip` holding fields together.
pub const HELD: usize = 1;

impl Touch {
    /// Both together.
    pub fn merge(self, o: Touch) -> Touch {
        let add = |a: [f64; 2], b: [f64; 2]| [a[0] + b[0], a[1] + b[1]];
        Touch {
            body_nodes: self.body_nodes + o.body_nodes,
            partner: o.partner.or(self.partner),
            walls: self.walls | o.walls,
            debonded: self.debonded + o.debonded,
            from_free: self.from_free + o.from_free,
            from_rigid: self.from_rigid + o.from_rigid,
            from_walls: self.from_walls + o.from_walls,
            work: add(self.work, o.work),
            grid: add(self.grid, o.grid),
            ke_grid: self.ke_grid + o.ke_grid,
            ke_points: self.ke_points + o.ke_points,
        }
    }
}

/// How contact is resolved where more than two bodies meet.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Crowd {
    /// Pair by pair, each pair's changes equal and opposite (momentum is exact); rigid
    /// bodies take part as pairs too ([`crate::crowd`]).
    #[default]
    Pairwise,
    /// Each body against the lumped rest with its heaviest partner's law, a rigid body
    /// as the master of all (the rule before pairs; momentum is not exact where three
    /// bodies meet, and free bodies at a rigid body's node do not meet each other).
    Lumped,
}

/// What one body's contact correction reads besides its own patch.
#[derive(Clone, Copy)]
pub struct Others<'a> {
    /// The sums over bodies, column-major.
    pub global: &'a [GlobalNode],
    /// The bond sums, same indexing (empty without bonded laws).
    pub bond: &'a [GlobalBond],
    /// Stored rows of the global grid.
    pub rows: usize,
    /// Row arithmetic of a periodic y (a patch's image rows meet the others at their
    /// canonical rows).
    pub wrap: Option<Rows>,
    /// Cell size (m).
    pub h: f64,
    /// Laws per pair.
    pub table: &'a ContactTable,
    /// Nairn's separation cut-off (see [`touching_separation`]).
    pub separation: Option<f64>,
    /// Density of each body's material (for the interface length at a node).
    pub density: &'a [f64],
    /// Pairwise contact: leave the nodes [`crate::crowd`] resolves.
    pub pairwise: bool,
    /// This pass's corrections reach the particles: count their impulses and energies.
    pub counts: bool,
}

impl Others<'_> {
    /// Global index of the node in patch column `c`, row `r` of `patch`.
    #[inline]
    pub fn at(&self, patch: &Patch, c: usize, r: usize) -> usize {
        let col = (patch.lo[0] + c) * self.rows;
        match self.wrap {
            None => col + patch.lo[1] + r,
            Some(w) => col + w.canonical(patch.lo[1] + r),
        }
    }
}

#[inline]
fn apply(n: &mut Node, dp: DVec2, pass: Pass, inv_dt: f64, bit: u32) {
    n.p += dp;
    if pass == Pass::Integrated {
        n.f += dp * inv_dt;
    }
    n.touched |= bit;
}

/// How far apart touching bodies' material centroids sit at a node, in cells: the largest
/// separation along the normal between two half-spaces of points that touch, over all
/// positions of the interface between two nodes. Found by laying out points as the
/// lattice fill does (`per_cell` per cell) and evaluating the shape function, so it holds
/// for any kernel and point density.
pub fn touching_separation(shape: ShapeFunction, per_cell: u32) -> f64 {
    match shape {
        ShapeFunction::Linear => touching::<Linear>(per_cell),
        ShapeFunction::Gimp => touching::<Gimp>(per_cell),
        ShapeFunction::Bspline2 => touching::<Bspline2>(per_cell),
    }
}

fn touching<K: Kernel>(per_cell: u32) -> f64 {
    let pitch = 1.0 / per_cell as f64;
    let lp = 0.5 * pitch;
    // Mass and first moment at node `node` of points x0 + (k + ½)·dir·pitch, k ≥ 0.
    let moments = |x0: f64, dir: f64, node: i64| {
        let (mut m, mut mx) = (0.0, 0.0);
        for k in 0..(8 * per_cell) {
            let x = x0 + dir * (k as f64 + 0.5) * pitch;
            let a = K::axis(x + 8.0, lp);
            for (j, w) in a.w.iter().enumerate() {
                if a.base as i64 + j as i64 - 8 == node {
                    m += w;
                    mx += w * x;
                }
            }
        }
        (m, mx)
    };
    let mut body = 0.0f64;
    for step in 0..64 {
        let o = step as f64 / 64.0;
        // Interface at x = o between nodes 0 and 1; the nearer node decides.
        let node = if o < 0.5 { 0 } else { 1 };
        let (mb, xb) = moments(o, -1.0, node);
        let (mr, xr) = moments(o, 1.0, node);
        if mb > 0.0 && mr > 0.0 {
            body = body.max(xr / mr - xb / mb);
        }
    }
    body
}

/// Where a body's field `n` at a node meets the others: the momentum it would take to move with
/// them (the centre of mass, or a rigid master), its unit outward normal and the length
/// of the normal vector |g_b − g_other| (`None` for the normal where the gradients cancel).
#[inline]
fn meeting(n: &Node, g: &GlobalNode) -> (DVec2, Option<(DVec2, f64)>) {
    // A rigid body is the master surface: its own normal is used, because a deformable
    // body's corner (where its gradient tilts) would otherwise plough into a flat rigid
    // surface it slides on.
    let (target, normal) = if g.m_rigid > 0.0 {
        (g.p_rigid * (n.m / g.m_rigid), -g.g_rigid)
    } else {
        (g.p * (n.m / g.m), 2.0 * n.g - g.g)
    };
    let len = normal.length();
    let normal = (len > 0.0 && len.is_finite()).then(|| (normal / len, len));
    (target, normal)
}

/// The interface length a node stands for: the normal vector's length over the densities
/// it sums, |g_b − g_other| = (ρ_b + ρ_other) × length (a rigid master's gradient alone).
#[inline]
fn length(b: u16, partner: u16, g: &GlobalNode, len: f64, density: &[f64]) -> f64 {
    let rho = if g.m_rigid > 0.0 {
        density[partner as usize]
    } else {
        density[b as usize] + density[partner as usize]
    };
    len / rho
}

/// Bonded pairs, after integration and before any correction: the normal force each
/// intact bond must carry to keep body `b` attached (its stick change over Δt along the
/// normal) and the interface length the node stands for, into the patch's bond records.
pub fn bond_forces(b: u16, patch: &mut Patch, others: &Others, dt: f64) {
    let rows = patch.size[1];
    for c in 0..patch.size[0] {
        for r in 0..rows {
            let at = others.at(patch, c, r);
            let n = &patch.nodes[c * rows + r];
            let rec = &mut patch.bond[c * rows + r];
            (rec.force, rec.length) = (0.0, 0.0);
            let g = &others.global[at];
            if g.count < 2 || n.m <= 0.0 || rec.failed {
                continue;
            }
            let partner = g.partner(b);
            let ContactLaw::Bonded { strength, .. } =
                others.table.get(b as usize, partner as usize)
            else {
                continue;
            };
            if others.bond[at].strength.min(strength) <= 0.0 {
                continue;
            }
            if let (target, Some((normal, len))) = meeting(n, g) {
                rec.force = (target - n.p).dot(normal) / dt;
                rec.length = length(b, partner, g, len, others.density);
            }
        }
    }
}

/// What body `b`'s change `dp` of its field at node `g` exchanges: momentum from the
/// others, and a rigid master's work dp·v_rigid, of kind `kind`.
fn count(touch: &mut Touch, dp: DVec2, g: &GlobalNode, kind: usize) {
    if g.m_rigid > 0.0 {
        touch.from_rigid += dp;
        touch.work[kind] += dp.dot(g.p_rigid) / g.m_rigid;
    } else {
        touch.from_free += dp;
    }
}

/// Corrects body `b`'s patch against the other bodies summed in `others.global`. With
/// a separation cut-off, nodes where the two sides' material centroids are farther apart
/// than that along the normal are left alone (the bodies are near, not touching). Bonds
/// are tested after integration against the smoothed traction of [`bond_forces`]; a node
/// where one fails is marked in the patch, is debonded for the rest of the step, and its
/// points lose their bond.
pub fn bodies(b: u16, patch: &mut Patch, others: &Others, pass: Pass, dt: f64) -> Touch {
    let mut touch = Touch::default();
    let rows = patch.size[1];
    let inv_dt = 1.0 / dt;
    let keep = !patch.xs.is_empty();
    let (table, separation) = (others.table, others.separation);
    for c in 0..patch.size[0] {
        for r in 0..rows {
            let k = c * rows + r;
            let at = others.at(patch, c, r);
            let g = &others.global[at];
            if g.count < 2 || patch.nodes[k].m <= 0.0 {
                continue;
            }
            if others.pairwise && crate::crowd::crowded(g) {
                continue;
            }
            let xs = if keep {
                patch.position_sum(k, others.wrap, others.h)
            } else {
                DVec2::ZERO
            };
            let n = &mut patch.nodes[k];
            let partner = g.partner(b);
            let law = table.get(b as usize, partner as usize);
            let (target, normal) = meeting(n, g);
            // A bond's state here: its strength (0 once failed), the traction it
            // carries (tested after integration), and the normal traction of the
            // stresses (for the compression test once debonded).
            let bonded = match law {
                ContactLaw::Bonded { strength, mu } => {
                    let gb = &others.bond[at];
                    let s = if patch.bond[k].failed {
                        0.0
                    } else {
                        gb.strength.min(strength)
                    };
                    let pull = (pass == Pass::Integrated).then_some(gb.traction);
                    let t = normal.map_or(0.0, |(n, _)| {
                        let [xx, yy, xy] = gb.ms.map(|x| x / g.m);
                        n.x * n.x * xx + 2.0 * n.x * n.y * xy + n.y * n.y * yy
                    });
                    Some((s, pull, t, mu))
                }
                _ => None,
            };
            let intact = bonded.is_some_and(|b| b.0 > 0.0);
            let Some((normal, _)) = normal else {
                // No normal: only an intact bond still acts (the fields move as one).
                if intact {
                    let dp = target - n.p;
                    if others.counts {
                        count(&mut touch, dp, g, HELD);
                        patch.record(k, pass as usize, HELD, dp);
                    }
                    apply(&mut patch.nodes[k], dp, pass, inv_dt, 1);
                    touch.body_nodes += 1;
                    touch.partner = Some(partner);
                }
                continue;
            };
            if let (Some(cut), true, false) =
                (separation, keep, intact || law == ContactLaw::NoSlip)
            {
                let mine = xs / n.m;
                let theirs = if g.m_rigid > 0.0 {
                    g.x_rigid / g.m_rigid
                } else {
                    (g.x - xs) / (g.m - n.m)
                };
                if (theirs - mine).dot(normal) > cut {
                    continue;
                }
            }
            let (dp, held) = match bonded {
                Some((s, pull, t, mu)) => {
                    let (dp, failed) = bond::bonded(target - n.p, normal, pull, t, s, mu);
                    if failed {
                        patch.bond[k].failed = true;
                        touch.debonded += 1;
                    }
                    (dp, s > 0.0)
                }
                None => (
                    coulomb(target - n.p, normal, law),
                    law == ContactLaw::NoSlip,
                ),
            };
            if let Some(dp) = dp {
                let kind = if held { HELD } else { SLIDE };
                if others.counts {
                    count(&mut touch, dp, g, kind);
                    patch.record(k, pass as usize, kind, dp);
                }
                apply(&mut patch.nodes[k], dp, pass, inv_dt, 1);
                touch.body_nodes += 1;
                touch.partner = Some(partner);
            }
        }
    }
    touch
}

/// Outward normals of the four sides.
const NORMALS: [DVec2; 4] = [
    DVec2::new(-1.0, 0.0),
    DVec2::new(1.0, 0.0),
    DVec2::new(0.0, -1.0),
    DVec2::new(0.0, 1.0),
];

/// Corrects a patch against the domain walls: every node on or beyond a walled edge
/// A wall needs no separation test: its node line is the wall, and approach alone is the
/// paper's criterion with exact normals.
pub fn walls(
    patch: &mut Patch,
    grid: &Grid,
    walls: &[Option<f64>; 4],
    pass: Pass,
    counts: bool,
    dt: f64,
) -> Touch {
    let mut touch = Touch::default();
    let inv_dt = 1.0 / dt;
    // Stored index of the edge nodes: left/bottom at GHOST, right/top at cells + GHOST.
    let edge = [GHOST, grid.cells[0] + GHOST, GHOST, grid.cells[1] + GHOST];
    let rows = patch.size[1];
    let (c0, c1) = patch.columns();
    let (r0, r1) = (patch.lo[1], patch.lo[1] + rows);
    for (side, mu) in walls.iter().enumerate() {
        let Some(mu) = *mu else { continue };
        let (cols, rws) = match side {
            0 => (c0..(edge[0] + 1).min(c1), r0..r1),
            1 => (edge[1].max(c0)..c1, r0..r1),
            2 => (c0..c1, r0..(edge[2] + 1).min(r1)),
            _ => (c0..c1, edge[3].max(r0)..r1),
        };
        let law = ContactLaw::Coulomb { mu };
        let normal = NORMALS[side];
        for col in cols {
            for row in rws.clone() {
                let k = (col - c0) * rows + (row - r0);
                let n = &mut patch.nodes[k];
                if n.m <= 0.0 {
                    continue;
                }
                // Stick change: bring the node to rest against the wall.
                if let Some(dp) = coulomb(-n.p, normal, law) {
                    if counts {
                        touch.from_walls += dp;
                        if !patch.ledger.is_empty() {
                            patch.ledger[k].dv[pass as usize][SLIDE] += dp / n.m;
                        }
                    }
                    apply(n, dp, pass, inv_dt, 2 << side);
                    touch.walls |= 1 << side;
                }
            }
        }
    }
    touch
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coulomb_cases() {
        let n = DVec2::new(0.0, 1.0);
        // Separating: nothing.
        assert_eq!(
            coulomb(DVec2::new(0.3, 0.5), n, ContactLaw::Coulomb { mu: 0.5 }),
            None
        );
        // Frictionless: normal part only.
        assert_eq!(
            coulomb(DVec2::new(0.3, -0.5), n, ContactLaw::Coulomb { mu: 0.0 }),
            Some(DVec2::new(0.0, -0.5))
        );
        // Sliding: tangential capped at μ|dn|.
        let d = coulomb(DVec2::new(0.3, -0.5), n, ContactLaw::Coulomb { mu: 0.2 }).unwrap();
        assert!((d - DVec2::new(0.1, -0.5)).length() < 1e-15);
        // Sticking: the whole change.
        let d = coulomb(DVec2::new(0.3, -0.5), n, ContactLaw::Coulomb { mu: 1.0 }).unwrap();
        assert_eq!(d, DVec2::new(0.3, -0.5));
        assert_eq!(
            coulomb(DVec2::new(0.3, 0.5), n, ContactLaw::NoSlip),
            Some(DVec2::new(0.3, 0.5))
        );
    }

    #[test]
    fn touching_separations() {
        // uGIMP, 2 × 2 points per cell: 0.75–0.86 h (Nairn's cut-off for this case is
        // ≈ 0.8 h).
        let b = touching_separation(ShapeFunction::Gimp, 2);
        assert!((0.8..0.9).contains(&b), "{b}");
        for s in [ShapeFunction::Linear, ShapeFunction::Bspline2] {
            let b = touching_separation(s, 2);
            assert!(b > 0.5 && b < 1.5, "{s:?}: {b}");
        }
    }

    #[test]
    fn wall_stops_approach_with_friction() {
        let grid = Grid {
            lo: DVec2::ZERO,
            h: 1.0,
            cells: [4, 4],
            periodic_y: false,
        };
        let mut patch = Patch::default();
        patch.reset([0, 0], [3, 3], false, false, false);
        for n in &mut patch.nodes {
            n.m = 2.0;
            n.p = DVec2::new(-1.0, 0.4);
        }
        let t = walls(
            &mut patch,
            &grid,
            &[Some(0.1), None, None, None],
            Pass::Integrated,
            true,
            0.5,
        );
        assert_eq!(t.walls, 1);
        // Six nodes each lose (1, −0.1): the wall's impulse.
        assert!((t.from_walls - DVec2::new(6.0, -0.6)).length() < 1e-14);
        // Columns 0 and 1 (ghost and edge) are corrected, column 2 is not.
        assert!((patch.nodes[0].p - DVec2::new(0.0, 0.3)).length() < 1e-15);
        assert!((patch.nodes[3].p - DVec2::new(0.0, 0.3)).length() < 1e-15);
        assert!((patch.nodes[3].f - DVec2::new(2.0, -0.2)).length() < 1e-15);
        assert_eq!(patch.nodes[6].p, DVec2::new(-1.0, 0.4));
    }
}
