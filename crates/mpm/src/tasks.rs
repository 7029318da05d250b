//! How one step's scratch is handed out to parallel tasks: each strip of the layout gets
//! its own slice of the points' fields, of the stencil cache and (for scatters, one
//! colour at a time) of its body's grid patch, so tasks never share what they write.

use crate::material::Stress;
use crate::nodes::{Kin, Node, Patch};
use crate::particles::{strip_columns, Layout, Particles};
use crate::transfer::{Points, Source, Stencil, View};
use glam::{DMat2, DVec2};

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
        let keep = !patch.xs.is_empty();
        let mut xs: &mut [DVec2] = &mut patch.xs;
        let mut cur = p0;
        while let Some(&(k, &(sb, strip, _, _))) = strips.peek() {
            if sb as usize != b {
                break;
            }
            strips.next();
            let (a, z) = strip_columns(strip as usize);
            let (a, z) = (a.max(cur), z.min(p1).max(a.max(cur)));
            let (_, rest) = std::mem::take(&mut nodes).split_at_mut((a - cur) * rows);
            let (mine, rest) = rest.split_at_mut((z - a) * rows);
            nodes = rest;
            let (_, krest) = std::mem::take(&mut kin).split_at_mut((a - cur) * rows);
            let (kmine, krest) = krest.split_at_mut((z - a) * rows);
            kin = krest;
            let xmine = if keep {
                let (_, xrest) = std::mem::take(&mut xs).split_at_mut((a - cur) * rows);
                let (xmine, xrest) = xrest.split_at_mut((z - a) * rows);
                xs = xrest;
                xmine
            } else {
                &mut []
            };
            cur = z;
            out.push((
                k,
                View {
                    col0: a,
                    row0,
                    rows,
                    nodes: mine,
                    kin: kmine,
                    xs: xmine,
                },
            ));
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
    }
}

/// The stencil cache split into one piece per strip of the layout.
pub fn split_cache<'a>(
    cache: &'a mut [Stencil],
    layout: &Layout,
) -> Vec<Option<&'a mut [Stencil]>> {
    let mut rest = cache;
    layout
        .strips
        .iter()
        .map(|&(_, _, start, end)| {
            let (a, r) = std::mem::take(&mut rest).split_at_mut(end - start);
            rest = r;
            Some(a)
        })
        .collect()
}

/// The mutable point fields a gather splits.
pub type Fields<'a> = (
    &'a mut [DVec2],
    &'a mut [DVec2],
    &'a mut [DMat2],
    &'a mut [Stress],
);

pub fn fields(p: &mut Particles) -> Fields<'_> {
    (&mut p.pos, &mut p.vel, &mut p.def, &mut p.stress)
}

/// Splits the points' mutable fields into one piece per strip of the layout.
pub fn split_points<'a>(
    fields: Fields<'a>,
    layout: &Layout,
    next: Option<&'a mut [DVec2]>,
) -> Vec<Option<Points<'a>>> {
    let (mut pos, mut vel, mut def, mut stress) = fields;
    let mut next = next;
    let mut out = Vec::with_capacity(layout.strips.len());
    for &(_, _, start, end) in &layout.strips {
        let n = end - start;
        let (a, r) = std::mem::take(&mut pos).split_at_mut(n);
        pos = r;
        let (b, r) = std::mem::take(&mut vel).split_at_mut(n);
        vel = r;
        let (c, r) = std::mem::take(&mut def).split_at_mut(n);
        def = r;
        let (d, r) = std::mem::take(&mut stress).split_at_mut(n);
        stress = r;
        let e = next.take().map(|nx| {
            let (e, r) = nx.split_at_mut(n);
            next = Some(r);
            e
        });
        out.push(Some(Points {
            pos: a,
            vel: b,
            def: c,
            stress: d,
            next: e,
        }));
    }
    out
}
