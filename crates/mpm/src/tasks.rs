//! How one step's scratch is handed out to parallel tasks: each strip of the layout gets
//! its own slice of the points' fields, of the stencil cache and (for scatters, one
//! colour at a time) of its body's grid patch, so tasks never share what they write.

use crate::models::MaterialView;
use crate::nodes::{BondNode, Kin, Node, Patch};
use crate::particles::{strip_columns, Layout, Particles};
use crate::transfer::{Points, Source, Stencil, View};
use glam::DVec2;

/// Skips `skip` entries of `rest` and hands out the next `take`; an empty `rest` (an
/// optional field not kept) hands out empty slices.
fn carve<'a, T>(rest: &mut &'a mut [T], skip: usize, take: usize) -> &'a mut [T] {
    if rest.is_empty() {
        return &mut [];
    }
    let (_, r) = std::mem::take(rest).split_at_mut(skip);
    let (mine, r) = r.split_at_mut(take);
    *rest = r;
    mine
}

/// The same-colour strips' windows onto the patches, with the layout entry they serve.
pub fn views<'a>(patches: &'a mut [Patch], layout: &Layout, colour: u32) -> Vec<(usize, View<'a>)> {
    let mut out = Vec::new();
    let mut strips = layout
        .strips
        .iter()
        .enumerate()
        .filter(|(_, st)| st.1 % 2 == colour)
        .peekable();
    for (b, patch) in patches.iter_mut().enumerate() {
        let rows = patch.size[1];
        let row0 = patch.lo[1];
        let (p0, p1) = patch.columns();
        let mut nodes: &mut [Node] = &mut patch.nodes;
        let mut kin: &mut [Kin] = &mut patch.kin;
        let mut xs: &mut [DVec2] = &mut patch.xs;
        let mut bond: &mut [BondNode] = &mut patch.bond;
        let mut cur = p0;
        while let Some(&(k, &(sb, strip, _, _))) = strips.peek() {
            if sb as usize != b {
                break;
            }
            strips.next();
            let (a, z) = strip_columns(strip as usize);
            let (a, z) = (a.max(cur), z.min(p1).max(a.max(cur)));
            let (skip, take) = ((a - cur) * rows, (z - a) * rows);
            let view = View {
                col0: a,
                row0,
                rows,
                nodes: carve(&mut nodes, skip, take),
                kin: carve(&mut kin, skip, take),
                xs: carve(&mut xs, skip, take),
                bond: carve(&mut bond, skip, take),
            };
            cur = z;
            out.push((k, view));
        }
    }
    out
}

pub fn source(p: &Particles) -> Source<'_> {
    Source {
        mass: &p.mass,
        vol0: &p.vol0,
        pos: &p.pos,
        vel: &p.vel,
        def: &p.def,
        stress: &p.stress,
        bond: &p.bond,
    }
}

/// Splits `v` (`width` entries per point) into one piece per strip of the layout.
pub fn split<'a, T>(v: &'a mut [T], layout: &Layout, width: usize) -> Vec<&'a mut [T]> {
    let mut rest = v;
    layout
        .strips
        .iter()
        .map(|&(_, _, start, end)| {
            let (a, r) = std::mem::take(&mut rest).split_at_mut((end - start) * width);
            rest = r;
            a
        })
        .collect()
}

/// The stencil cache split into one piece per strip of the layout.
pub fn split_cache<'a>(
    cache: &'a mut [Stencil],
    layout: &Layout,
) -> Vec<Option<&'a mut [Stencil]>> {
    split(cache, layout, 1).into_iter().map(Some).collect()
}

/// Splits the points' mutable fields into one piece per strip of the layout.
pub fn split_points<'a>(
    p: &'a mut Particles,
    layout: &Layout,
    next: Option<&'a mut [DVec2]>,
) -> Vec<Option<Points<'a>>> {
    let w = p.branch_width;
    let vol0 = &p.vol0;
    let mass = &p.mass;
    let mut pos = split(&mut p.pos, layout, 1).into_iter();
    let mut vel = split(&mut p.vel, layout, 1).into_iter();
    let mut def = split(&mut p.def, layout, 1).into_iter();
    let mut stress = split(&mut p.stress, layout, 1).into_iter();
    let mut plastic = split(&mut p.plastic, layout, 1).into_iter();
    let mut dissipated = split(&mut p.dissipated, layout, 1).into_iter();
    let mut thermal = split(&mut p.thermal_work, layout, 1).into_iter();
    let mut branches = split(&mut p.branches, layout, w).into_iter();
    let mut next = next.map(|n| split(n, layout, 1).into_iter());
    layout
        .strips
        .iter()
        .map(|&(_, _, start, end)| {
            let mut take = || -> Option<Points<'a>> {
                Some(Points {
                    mass: &mass[start..end],
                    pos: pos.next()?,
                    vel: vel.next()?,
                    mat: MaterialView {
                        vol0: &vol0[start..end],
                        def: def.next()?,
                        stress: stress.next()?,
                        plastic: plastic.next()?,
                        dissipated: dissipated.next()?,
                        thermal_work: thermal.next()?,
                        branches: branches.next()?,
                        width: w,
                    },
                    next: match next.as_mut() {
                        Some(n) => Some(n.next()?),
                        None => None,
                    },
                })
            };
            take()
        })
        .collect()
}
