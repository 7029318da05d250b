//! Particle ↔ grid transfers, generic over the shape function so each kernel is
//! compiled (and unrolled) once per `Kernel`. Scatters run one strip of one body per
//! task on that strip's own slice of the body's patch; gathers only read the grid.

use crate::grid::GHOST;
use crate::material::Stress;
use crate::models::{MaterialView, Model};
use crate::nodes::{BondNode, Kin, Node};
use crate::particles::within_strip;
use crate::shape::Kernel;
use crate::simd::multiversion;
use glam::{DMat2, DVec2};

/// What every transfer needs to place a point on the grid.
#[derive(Clone, Copy, Debug)]
pub struct Place {
    /// Domain corner.
    pub lo: DVec2,
    /// 1 / cell size.
    pub inv_h: f64,
    /// GIMP half-width (grid units).
    pub lp: f64,
    /// Along a periodic y: the domain's lower y and the period (points that cross the
    /// seam come back on the other side).
    pub wrap_y: Option<(f64, f64)>,
}

/// Weights of one point: 3 × 3 tensor-product stencil from stored node `(col, row)`.
/// Computed once per step by the P2G scatter and kept: every later pass of the step
/// sees the points at the same positions.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stencil {
    /// First stored column.
    pub col: usize,
    /// First stored row.
    pub row: usize,
    /// Weights along x.
    pub wx: [f64; 3],
    /// Weights along y.
    pub wy: [f64; 3],
    /// dS/dx along x (per m).
    pub dx: [f64; 3],
    /// dS/dy along y (per m).
    pub dy: [f64; 3],
}

impl Place {
    /// Where a point that moved to `x` is kept: `x`, or along a periodic y its image in
    /// the domain.
    #[inline(always)]
    pub fn keep(&self, mut x: DVec2) -> DVec2 {
        if let Some((lo, l)) = self.wrap_y {
            if x.y >= lo + l {
                x.y -= l;
            } else if x.y < lo {
                x.y += l;
            }
        }
        x
    }

    /// The stencil of a point at `x`.
    #[inline(always)]
    pub fn stencil<K: Kernel>(&self, x: DVec2) -> Stencil {
        let xi = (x - self.lo) * self.inv_h + GHOST as f64;
        let ax = K::axis(xi.x, self.lp);
        let ay = K::axis(xi.y, self.lp);
        Stencil {
            col: ax.base,
            row: ay.base,
            wx: ax.w,
            wy: ay.w,
            dx: ax.dw.map(|d| d * self.inv_h),
            dy: ay.dw.map(|d| d * self.inv_h),
        }
    }
}

/// A strip's window onto one body's patch: stored columns from `col0`, rows from `row0`,
/// `rows` rows per column.
pub struct View<'a> {
    /// First stored column of the slices.
    pub col0: usize,
    /// First stored row of the patch.
    pub row0: usize,
    /// Rows per column.
    pub rows: usize,
    /// Node fields.
    pub nodes: &'a mut [Node],
    /// Kinematics.
    pub kin: &'a mut [Kin],
    /// Σ S m x, or empty when positions are not kept.
    pub xs: &'a mut [DVec2],
    /// Interface stress and bond sums, or empty when no contact law bonds.
    pub bond: &'a mut [BondNode],
}

impl View<'_> {
    #[inline(always)]
    fn at(&self, s: &Stencil, a: usize, b: usize) -> usize {
        (s.col + a - self.col0) * self.rows + (s.row + b - self.row0)
    }
}

/// Read-only view of the points a kernel scatters from.
#[derive(Clone, Copy)]
pub struct Source<'a> {
    /// Masses.
    pub mass: &'a [f64],
    /// Reference volumes.
    pub vol0: &'a [f64],
    /// Positions.
    pub pos: &'a [DVec2],
    /// Velocities.
    pub vel: &'a [DVec2],
    /// Deformation gradients.
    pub def: &'a [DMat2],
    /// Stresses.
    pub stress: &'a [Stress],
    /// Bond strengths.
    pub bond: &'a [f64],
}

multiversion! {
/// P2G of mass and momentum, plus (`FORCE`) the internal force −V σ·∇S, (`GRAD`) the
/// contact geometry: mass gradient Σ m ∇S and, if kept, Σ S m x, and (`BOND`, with
/// `GRAD`) what a bonded interface needs: Σ S m σ and the largest bond of the points that
/// reach each node, for points `range`.
#[allow(clippy::too_many_arguments)]
pub fn scatter[K: Kernel, const FORCE: bool, const GRAD: bool, const BOND: bool][K, FORCE, GRAD, BOND](
    place: &Place,
    src: Source,
    range: (usize, usize),
    view: &mut View,
    cache: &mut [Stencil],
) {
    for i in range.0..range.1 {
        let x = src.pos[i];
        let s = place.stencil::<K>(x);
        cache[i - range.0] = s;
        let m = src.mass[i];
        let mv = m * src.vel[i];
        let (sxx, syy, sxy) = if FORCE {
            let st = src.stress[i];
            let v = src.vol0[i] * src.def[i].determinant();
            (st.xx * v, st.yy * v, st.xy * v)
        } else {
            (0.0, 0.0, 0.0)
        };
        let first = view.at(&s, 0, 0);
        if BOND {
            let st = src.stress[i];
            let ms = [m * st.xx, m * st.yy, m * st.xy];
            let bond = src.bond[i];
            for a in 0..K::N {
                for b in 0..K::N {
                    let w = s.wx[a] * s.wy[b];
                    let n = &mut view.bond[first + a * view.rows + b];
                    for c in 0..3 {
                        n.ms[c] += w * ms[c];
                    }
                    if w > 0.0 {
                        n.strength = n.strength.max(bond);
                    }
                }
            }
        }
        for a in 0..K::N {
            let col = &mut view.nodes[first + a * view.rows..][..K::N];
            for b in 0..K::N {
                let w = s.wx[a] * s.wy[b];
                let n = &mut col[b];
                n.m += w * m;
                n.p += w * mv;
                if FORCE || GRAD {
                    let gx = s.dx[a] * s.wy[b];
                    let gy = s.wx[a] * s.dy[b];
                    if FORCE {
                        n.f.x -= sxx * gx + sxy * gy;
                        n.f.y -= sxy * gx + syy * gy;
                    }
                    if GRAD {
                        n.g.x += m * gx;
                        n.g.y += m * gy;
                    }
                }
                if GRAD && !view.xs.is_empty() {
                    view.xs[first + a * view.rows + b] += (w * m) * x;
                }
            }
        }
    }
}}

multiversion! {
/// P2G of momentum alone (MUSL's re-map of the updated velocities) at the positions the
/// step started from.
pub fn scatter_momentum[K: Kernel][K](
    src: Source,
    range: (usize, usize),
    view: &mut View,
    cache: &[Stencil],
) {
    for i in range.0..range.1 {
        let s = cache[i - range.0];
        let mv = src.mass[i] * src.vel[i];
        let first = view.at(&s, 0, 0);
        for a in 0..K::N {
            let col = &mut view.nodes[first + a * view.rows..][..K::N];
            for b in 0..K::N {
                col[b].p += (s.wx[a] * s.wy[b]) * mv;
            }
        }
    }
}}

/// Velocity gradient Σ v_i ⊗ ∇S_ip from the view's (or patch's) kinematics.
#[inline(always)]
fn velocity_gradient<K: Kernel>(
    s: &Stencil,
    kin: &[Kin],
    col0: usize,
    row0: usize,
    rows: usize,
) -> DMat2 {
    let mut l = DMat2::ZERO;
    let first = (s.col - col0) * rows + (s.row - row0);
    for a in 0..K::N {
        let col = &kin[first + a * rows..][..K::N];
        for b in 0..K::N {
            let v = col[b].v;
            let gx = s.dx[a] * s.wy[b];
            let gy = s.wx[a] * s.dy[b];
            l.x_axis += v * gx;
            l.y_axis += v * gy;
        }
    }
    l
}

/// Mutable per-point fields a gather writes.
pub struct Points<'a> {
    /// Masses.
    pub mass: &'a [f64],
    /// Positions (read; written unless `next` is given).
    pub pos: &'a mut [DVec2],
    /// Velocities.
    pub vel: &'a mut [DVec2],
    /// What the material updates: F, σ and the internal state.
    pub mat: MaterialView<'a>,
    /// Where new positions go when the old ones are still needed (MUSL).
    pub next: Option<&'a mut [DVec2]>,
}

multiversion! {
/// USF: gathers the strain rate from the interpolated velocities, updates the stress,
/// then scatters the internal force −V σ·∇S, in one pass over the strip.
pub fn stress_and_force[K: Kernel, M: Model][K, M](
    model: &M,
    pts: &mut MaterialView,
    view: &mut View,
    cache: &[Stencil],
) {
    for i in 0..pts.def.len() {
        let s = cache[i];
        let l = velocity_gradient::<K>(&s, view.kin, view.col0, view.row0, view.rows);
        model.update(l, pts, i);
        let v = pts.vol0[i] * pts.def[i].determinant();
        let st = pts.stress[i];
        let (sxx, syy, sxy) = (st.xx * v, st.yy * v, st.xy * v);
        let first = view.at(&s, 0, 0);
        for a in 0..K::N {
            let col = &mut view.nodes[first + a * view.rows..][..K::N];
            for b in 0..K::N {
                let gx = s.dx[a] * s.wy[b];
                let gy = s.wx[a] * s.dy[b];
                let n = &mut col[b];
                n.f.x -= sxx * gx + sxy * gy;
                n.f.y -= sxy * gx + syy * gy;
            }
        }
    }
}}

/// What a gather saw: the points' bounding box, and whether any point left its strip
/// (re-sort needed) or the domain / went non-finite (unstable).
#[derive(Clone, Copy, Debug)]
pub struct Seen {
    /// Lower corner of the new positions.
    pub min: DVec2,
    /// Upper corner.
    pub max: DVec2,
    /// Some point drifted out of its strip.
    pub drifted: bool,
    /// Some point left the domain or is not finite.
    pub escaped: bool,
    /// The points' kinetic energy change (with the ledger).
    pub ke: f64,
}

impl Seen {
    /// Nothing seen yet.
    pub fn empty() -> Self {
        Seen {
            min: DVec2::INFINITY,
            max: DVec2::NEG_INFINITY,
            drifted: false,
            escaped: false,
            ke: 0.0,
        }
    }

    /// Both together.
    pub fn merge(self, o: Seen) -> Seen {
        Seen {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
            drifted: self.drifted || o.drifted,
            escaped: self.escaped || o.escaped,
            ke: self.ke + o.ke,
        }
    }

    #[inline(always)]
    fn see(&mut self, x: DVec2, place: &Place, hi: DVec2, strip: usize) {
        self.min = self.min.min(x);
        self.max = self.max.max(x);
        if !(x.cmpge(place.lo).all() && x.cmple(hi).all()) {
            self.escaped = true;
            return;
        }
        let cx = ((x.x - place.lo.x) * place.inv_h) as i32 as usize;
        self.drifted |= !within_strip(cx, strip);
    }
}

multiversion! {
/// The grid-to-particle update of one strip: FLIP/PIC velocity, position, and (`STRESS`,
/// USL and USAVG) the stress from the updated grid velocity (the model carries its own
/// step, the whole or the second half of `dt`). With `KE`, the points' kinetic energy
/// change is summed (the energy ledger).
#[allow(clippy::too_many_arguments)]
pub fn gather[K: Kernel, M: Model, const STRESS: bool, const KE: bool][K, M, STRESS, KE](
    place: &Place,
    hi: DVec2,
    model: &M,
    dt: f64,
    flip: f64,
    patch: (&[Kin], [usize; 2], usize),
    strip: usize,
    pts: &mut Points,
    cache: &[Stencil],
) -> Seen {
    let (kin, lo, rows) = patch;
    let mut seen = Seen::empty();
    for i in 0..pts.pos.len() {
        let x = pts.pos[i];
        let s = cache[i];
        let mut v = DVec2::ZERO;
        let mut a_sum = DVec2::ZERO;
        let mut l = DMat2::ZERO;
        let first = (s.col - lo[0]) * rows + (s.row - lo[1]);
        for a in 0..K::N {
            let col = &kin[first + a * rows..][..K::N];
            for b in 0..K::N {
                let w = s.wx[a] * s.wy[b];
                let k = col[b];
                v += w * k.v;
                a_sum += w * k.a;
                if STRESS {
                    l.x_axis += k.v * (s.dx[a] * s.wy[b]);
                    l.y_axis += k.v * (s.wx[a] * s.dy[b]);
                }
            }
        }
        let old = pts.vel[i];
        let flipped = pts.vel[i] + dt * a_sum;
        pts.vel[i] = if flip == 1.0 {
            flipped
        } else {
            flip * flipped + (1.0 - flip) * v
        };
        if KE {
            seen.ke += 0.5 * pts.mass[i] * (pts.vel[i].length_squared() - old.length_squared());
        }
        let nx = place.keep(x + dt * v);
        match pts.next.as_deref_mut() {
            Some(next) => next[i] = nx,
            None => pts.pos[i] = nx,
        }
        seen.see(nx, place, hi, strip);
        if STRESS {
            model.update(l, &mut pts.mat, i);
        }
    }
    seen
}}

multiversion! {
/// MUSL's last pass: the strain rate from the re-mapped velocities at the old positions,
/// then the positions move on.
pub fn gather_stress[K: Kernel, M: Model][K, M](
    model: &M,
    patch: (&[Kin], [usize; 2], usize),
    pts: &mut Points,
    cache: &[Stencil],
) {
    let (kin, lo, rows) = patch;
    let next = pts
        .next
        .as_deref()
        .expect("MUSL keeps the new positions apart");
    for i in 0..pts.pos.len() {
        let s = cache[i];
        let l = velocity_gradient::<K>(&s, kin, lo[0], lo[1], rows);
        model.update(l, &mut pts.mat, i);
        pts.pos[i] = next[i];
    }
}}

/// A rigid body's points move with its prescribed velocity.
pub fn move_rigid(
    place: &Place,
    hi: DVec2,
    v: DVec2,
    dt: f64,
    strip: usize,
    pts: &mut Points,
) -> Seen {
    let mut seen = Seen::empty();
    for i in 0..pts.pos.len() {
        pts.vel[i] = v;
        let nx = place.keep(pts.pos[i] + dt * v);
        match pts.next.as_deref_mut() {
            Some(next) => next[i] = nx,
            None => pts.pos[i] = nx,
        }
        seen.see(nx, place, hi, strip);
    }
    seen
}
