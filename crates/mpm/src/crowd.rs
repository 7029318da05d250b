//! Contact where more than two bodies meet at a node, or where a rigid body meets
//! another: Bardenhagen's law applied pair by pair. Each pair of fields at the node is
//! moved toward its own centre of mass (a rigid body toward its prescribed velocity),
//! along the pair's colinear normal n ∝ g_a − g_b (a rigid body's own normal), with the
//! pair's law and separation test. The two changes of a pair are equal and opposite, so
//! whatever the order and the number of sweeps the node's momentum is exact; what a rigid
//! body gives its partners is its reaction. A node's pairs are swept in body order until
//! a sweep changes nothing (a pair that a later one pushed back together is corrected
//! again), at most [`SWEEPS`] times.
//!
//! With the lumped rule each body was moved toward the centre of mass of all the others
//! with the law of the heaviest: where three bodies meet the changes do not cancel once
//! one of them slides or separates, and free bodies at a rigid body's node only met the
//! rigid body. A node with one free body and one rigid body gives bitwise the lumped
//! rule's answer (the same operations).

use crate::bond;
use crate::contact::{coulomb, Others, Pass, Touch, HELD, SLIDE};
use crate::nodes::{GlobalNode, Patch};
use crate::setup::ContactLaw;
use glam::DVec2;
use rayon::prelude::*;

/// Most sweeps over a node's pairs.
pub const SWEEPS: usize = 8;

/// True if the node is resolved pair by pair: three or more bodies, or a rigid body
/// with another.
#[inline]
pub fn crowded(g: &GlobalNode) -> bool {
    g.count >= 3 || (g.count == 2 && g.m_rigid > 0.0)
}

/// One body's field at a crowded node.
#[derive(Clone, Copy, Debug)]
struct Entry {
    /// Global index of the node.
    node: usize,
    /// Local index in the body's patch.
    k: usize,
    m: f64,
    p: DVec2,
    g: DVec2,
    /// Σ S m x seen from the canonical row.
    xs: DVec2,
    /// The body's bond failed at this node earlier in the step.
    failed: bool,
}

/// What a node's pairs did to one body's field.
#[derive(Clone, Copy, Debug, Default)]
struct Change {
    dp: DVec2,
    /// The part of `dp` by kind of correction (counted passes only).
    kinds: [DVec2; 2],
    acted: bool,
    failed: bool,
    touch: Touch,
}

/// Scratch of the pairwise resolution, kept to reuse its allocations.
#[derive(Clone, Debug, Default)]
pub struct Crowds {
    entries: Vec<Vec<Entry>>,
    changes: Vec<Vec<Change>>,
    order: Vec<(usize, u16, u32)>,
    /// One node's fields, momenta and changes while its pairs are resolved.
    group: Vec<(u16, Entry)>,
    p: Vec<DVec2>,
    ch: Vec<Change>,
}

/// Resolves every crowded node of the patches: corrects the free bodies' fields
/// (and, after integration, their forces) and returns what each body exchanged.
/// `rigid[b]` says which bodies are rigid.
pub fn resolve(
    patches: &mut [Patch],
    others: &Others,
    rigid: &[bool],
    pass: Pass,
    dt: f64,
    scratch: &mut Crowds,
) -> Vec<Touch> {
    let nb = patches.len();
    scratch.entries.resize_with(nb, Vec::new);
    scratch.changes.resize_with(nb, Vec::new);
    patches
        .par_iter()
        .zip(scratch.entries.par_iter_mut())
        .for_each(|(patch, list)| collect(patch, others, list));
    scratch.order.clear();
    for (b, list) in scratch.entries.iter().enumerate() {
        scratch.order.extend(
            list.iter()
                .enumerate()
                .map(|(i, e)| (e.node, b as u16, i as u32)),
        );
    }
    scratch.order.sort_unstable();
    for (list, ch) in scratch.entries.iter().zip(scratch.changes.iter_mut()) {
        ch.clear();
        ch.resize(list.len(), Change::default());
    }
    let mut start = 0;
    while start < scratch.order.len() {
        let node = scratch.order[start].0;
        let mut end = start + 1;
        while end < scratch.order.len() && scratch.order[end].0 == node {
            end += 1;
        }
        let group = &scratch.order[start..end];
        scratch.group.clear();
        scratch.group.extend(
            group
                .iter()
                .map(|&(_, b, i)| (b, scratch.entries[b as usize][i as usize])),
        );
        let (p, ch) = (&mut scratch.p, &mut scratch.ch);
        node_pairs(&scratch.group, rigid, others, pass, p, ch);
        for (&(_, b, i), c) in group.iter().zip(ch.iter()) {
            scratch.changes[b as usize][i as usize] = *c;
        }
        start = end;
    }
    let inv_dt = 1.0 / dt;
    patches
        .par_iter_mut()
        .zip(scratch.entries.par_iter().zip(scratch.changes.par_iter()))
        .enumerate()
        .map(|(b, (patch, (list, changes)))| {
            let mut touch = Touch::default();
            for (e, c) in list.iter().zip(changes) {
                if !c.acted {
                    continue;
                }
                if !rigid[b] {
                    let n = &mut patch.nodes[e.k];
                    n.p += c.dp;
                    if pass == Pass::Integrated {
                        n.f += c.dp * inv_dt;
                    }
                    n.touched |= 1;
                    if others.counts {
                        patch.record(e.k, pass as usize, SLIDE, c.kinds[SLIDE]);
                        patch.record(e.k, pass as usize, HELD, c.kinds[HELD]);
                    }
                }
                if c.failed && !patch.bond.is_empty() {
                    patch.bond[e.k].failed = true;
                }
                touch = touch.merge(c.touch);
            }
            touch
        })
        .collect()
}

/// The crowded nodes of one patch.
fn collect(patch: &Patch, others: &Others, list: &mut Vec<Entry>) {
    list.clear();
    let rows = patch.size[1];
    let keep = !patch.xs.is_empty();
    for c in 0..patch.size[0] {
        for r in 0..rows {
            let k = c * rows + r;
            let n = &patch.nodes[k];
            if n.m <= 0.0 {
                continue;
            }
            let node = others.at(patch, c, r);
            if !crowded(&others.global[node]) {
                continue;
            }
            list.push(Entry {
                node,
                k,
                m: n.m,
                p: n.p,
                g: n.g,
                xs: if keep {
                    patch.position_sum(k, others.wrap, others.h)
                } else {
                    DVec2::ZERO
                },
                failed: !patch.bond.is_empty() && patch.bond[k].failed,
            });
        }
    }
}

/// The changes `ch` of the fields `entries` (body, field) at one node, pair by pair
/// (`p` holds their momenta as they change).
fn node_pairs(
    entries: &[(u16, Entry)],
    rigid: &[bool],
    others: &Others,
    pass: Pass,
    p: &mut Vec<DVec2>,
    ch: &mut Vec<Change>,
) {
    let n = entries.len();
    p.clear();
    p.extend(entries.iter().map(|(_, e)| e.p));
    ch.clear();
    ch.resize(n, Change::default());
    let node = entries[0].1.node;
    let gn = &others.global[node];
    // One pair is exact in one pass; more are swept until they agree.
    let sweeps = if n == 2 { 1 } else { SWEEPS };
    let scale: f64 = p.iter().map(|x| x.length()).sum::<f64>();
    for _ in 0..sweeps {
        let mut largest = 0.0f64;
        for i in 0..n {
            for j in i + 1..n {
                let (bi, bj) = (entries[i].0, entries[j].0);
                let (ri, rj) = (rigid[bi as usize], rigid[bj as usize]);
                if ri && rj {
                    continue;
                }
                let (a, o) = if ri { (j, i) } else { (i, j) };
                let Some(dp) = pair(entries, a, o, rj || ri, p, ch, gn, others, pass) else {
                    continue;
                };
                largest = largest.max(dp.length());
                p[a] += dp;
                ch[a].dp += dp;
                ch[a].acted = true;
                ch[o].acted = true;
                ch[a].touch.partner = Some(entries[o].0);
                ch[o].touch.partner = Some(entries[a].0);
                ch[a].touch.body_nodes = 1;
                ch[o].touch.body_nodes = 1;
                if !(ri || rj) {
                    p[o] -= dp;
                    ch[o].dp -= dp;
                }
            }
        }
        if largest <= 1e-14 * scale {
            break;
        }
    }
}

/// One pair's change of `a`'s field (`o`'s is its negative, or `o` is rigid); counts
/// what it exchanges into `ch` when the pass counts.
#[allow(clippy::too_many_arguments)]
fn pair(
    entries: &[(u16, Entry)],
    a: usize,
    o: usize,
    with_rigid: bool,
    p: &[DVec2],
    ch: &mut [Change],
    gn: &GlobalNode,
    others: &Others,
    pass: Pass,
) -> Option<DVec2> {
    let ((ba, ea), (bo, eo)) = (entries[a], entries[o]);
    let law = others.table.get(ba as usize, bo as usize);
    // A rigid body is the master surface: its prescribed velocity and its own normal (as
    // in the two-body rule).
    let (target, normal) = if with_rigid {
        (p[o] * (ea.m / eo.m), -eo.g)
    } else {
        let mass = ea.m + eo.m;
        ((p[a] + p[o]) * (ea.m / mass), ea.g - eo.g)
    };
    let len = normal.length();
    let normal = (len > 0.0 && len.is_finite()).then(|| normal / len);
    let failed_before = ea.failed || eo.failed || ch[a].failed || ch[o].failed;
    let bonded = match law {
        ContactLaw::Bonded { strength, mu } => {
            let gb = &others.bond[ea.node];
            let s = if failed_before {
                0.0
            } else {
                gb.strength.min(strength)
            };
            let pull = (pass == Pass::Integrated).then_some(gb.traction);
            let t = normal.map_or(0.0, |n| {
                let [xx, yy, xy] = gb.ms.map(|x| x / gn.m);
                n.x * n.x * xx + 2.0 * n.x * n.y * xy + n.y * n.y * yy
            });
            Some((s, pull, t, mu))
        }
        _ => None,
    };
    let intact = bonded.is_some_and(|b| b.0 > 0.0);
    let stick = target - p[a];
    let (dp, held) = match normal {
        // No normal: only an intact bond still acts (the fields move as one).
        None if intact => (stick, true),
        None => return None,
        Some(normal) => {
            if let (Some(cut), false) = (others.separation, intact || law == ContactLaw::NoSlip) {
                let (mine, theirs) = (ea.xs / ea.m, eo.xs / eo.m);
                if (theirs - mine).dot(normal) > cut {
                    return None;
                }
            }
            match bonded {
                Some((s, pull, t, mu)) => {
                    let (dp, failed) = bond::bonded(stick, normal, pull, t, s, mu);
                    if failed {
                        ch[a].failed = true;
                        ch[a].touch.debonded += 1;
                        if !with_rigid {
                            ch[o].failed = true;
                        }
                    }
                    (dp?, s > 0.0)
                }
                None => (coulomb(stick, normal, law)?, law == ContactLaw::NoSlip),
            }
        }
    };
    if others.counts {
        let kind = if held { HELD } else { SLIDE };
        ch[a].kinds[kind] += dp;
        if with_rigid {
            ch[a].touch.from_rigid += dp;
            ch[o].touch.from_rigid -= dp;
            ch[o].touch.work[kind] += dp.dot(p[o]) / eo.m;
        } else {
            ch[o].kinds[kind] -= dp;
            ch[a].touch.from_free += dp;
            ch[o].touch.from_free -= dp;
        }
    }
    Some(dp)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::setup::ContactTable;

    /// Fields (mass, velocity, mass gradient) of bodies 0.. at one node, and the sums.
    fn node(fields: &[(f64, DVec2, DVec2)], rigid: &[bool]) -> (Vec<(u16, Entry)>, GlobalNode) {
        let mut g = GlobalNode::default();
        let entries = fields
            .iter()
            .enumerate()
            .map(|(b, &(m, v, grad))| {
                g.m += m;
                g.p += m * v;
                g.count += 1;
                if rigid[b] {
                    g.m_rigid += m;
                }
                let e = Entry {
                    node: 0,
                    k: 0,
                    m,
                    p: m * v,
                    g: grad,
                    xs: DVec2::ZERO,
                    failed: false,
                };
                (b as u16, e)
            })
            .collect();
        (entries, g)
    }

    fn others<'a>(g: &'a [GlobalNode], table: &'a ContactTable) -> Others<'a> {
        Others {
            global: g,
            bond: &[],
            rows: 1,
            wrap: None,
            h: 1.0,
            table,
            separation: None,
            density: &[1.0; 4],
            pairwise: true,
            counts: true,
        }
    }

    /// The relative normal velocity of fields a and b along a's outward normal after the
    /// changes (> 0: approaching).
    fn approach(e: &[(u16, Entry)], ch: &[Change], a: usize, b: usize) -> f64 {
        let v = |i: usize| (e[i].1.p + ch[i].dp) / e[i].1.m;
        let n = (e[a].1.g - e[b].1.g).normalize();
        (v(a) - v(b)).dot(n)
    }

    #[test]
    fn three_bodies_sliding_keep_momentum_exactly() {
        // Three grains closing in on one node from 120° apart (mass gradients point out of
        // a body, toward the node), each also moving sideways: all pairs slide, μ = 0.3.
        let dir = |deg: f64| DVec2::from_angle(deg.to_radians());
        let fields = [
            (1.0, 0.3 * dir(90.0) + 0.2 * dir(0.0), dir(90.0)),
            (2.0, 0.2 * dir(210.0) + 0.1 * dir(120.0), dir(210.0)),
            (0.7, 0.4 * dir(330.0) - 0.3 * dir(240.0), dir(330.0)),
        ];
        let (e, g) = node(&fields, &[false; 3]);
        let table = ContactTable::new(3, ContactLaw::Coulomb { mu: 0.3 });
        let gl = [g];
        let (mut p, mut ch) = (Vec::new(), Vec::new());
        node_pairs(
            &e,
            &[false; 3],
            &others(&gl, &table),
            Pass::Integrated,
            &mut p,
            &mut ch,
        );
        let total: DVec2 = ch.iter().map(|c| c.dp).sum();
        let scale: f64 = e.iter().map(|(_, x)| x.p.length()).sum();
        assert!(total.length() <= 1e-15 * scale, "{total}");
        // After the sweeps no pair still approaches, and every pair was corrected.
        for (a, b) in [(0, 1), (0, 2), (1, 2)] {
            assert!(approach(&e, &ch, a, b) < 1e-12, "{a}-{b}");
        }
        assert!(ch.iter().all(|c| c.acted && c.dp.length() > 0.0));
        // Momentum exchanged between free bodies sums to zero; kinetic energy only goes
        // out; the sliding kind holds the whole change.
        let from: DVec2 = ch.iter().map(|c| c.touch.from_free).sum();
        assert!(from.length() <= 1e-15 * scale);
        let ke = |c: &[Change]| -> f64 {
            e.iter()
                .zip(c)
                .map(|((_, x), c)| (x.p + c.dp).length_squared() / (2.0 * x.m))
                .sum()
        };
        assert!(ke(&ch) < ke(&vec![Change::default(); 3]));
        assert!(ch
            .iter()
            .all(|c| c.kinds[SLIDE] == c.dp && c.kinds[HELD] == DVec2::ZERO));
    }

    #[test]
    fn free_bodies_meet_each_other_at_a_rigid_bodys_node() {
        // A rigid floor (body 0, at rest) and two grains above it closing in on each other
        // along x: the grains' own contact acts, and the floor's reaction is what it gave.
        let fields = [
            (3.0, DVec2::ZERO, DVec2::new(0.0, 1.0)),
            (1.0, DVec2::new(0.2, -0.05), DVec2::new(1.0, -0.3)),
            (1.0, DVec2::new(-0.2, -0.05), DVec2::new(-1.0, -0.3)),
        ];
        let rigid = [true, false, false];
        let (e, g) = node(&fields, &rigid);
        let table = ContactTable::new(3, ContactLaw::Coulomb { mu: 0.0 });
        let gl = [g];
        let (mut p, mut ch) = (Vec::new(), Vec::new());
        node_pairs(
            &e,
            &rigid,
            &others(&gl, &table),
            Pass::Integrated,
            &mut p,
            &mut ch,
        );
        assert_eq!(ch[0].dp, DVec2::ZERO, "a rigid body is not moved");
        assert!(
            approach(&e, &ch, 1, 2) < 1e-12,
            "the grains stop closing in"
        );
        for b in [1, 2] {
            let v = (e[b].1.p + ch[b].dp) / e[b].1.m;
            assert!(v.y > -1e-12, "grain {b} still sinks into the floor: {v}");
        }
        let received = ch[1].touch.from_rigid + ch[2].touch.from_rigid;
        assert!((ch[0].touch.from_rigid + received).length() < 1e-15);
        assert!(received.y > 0.0);
        assert_eq!(ch[0].touch.work, [0.0; 2], "a floor at rest does no work");
    }
}
