//! Material points, stored per field, kept sorted by (body, strip, cell) so that each
//! body's points are contiguous and each body splits into strips of grid columns that
//! can be scattered to the grid in parallel without two threads touching one node.
//! Internal state (plastic strain, Maxwell branches, bond strength, energy accounts) is
//! stored per field like the rest; a model reads only the fields it needs.

use crate::grid::Grid;
use crate::material::Stress;
use crate::models::MaterialView;
use glam::{DMat2, DVec2};

/// Width of a strip in cells.
pub const STRIP: usize = 8;
/// How far (cells) a point may drift out of its strip before the points are re-sorted.
/// Same-colour strips stay disjoint while `STRIP ≥ 2·DRIFT + 3` (a 3-node stencil).
pub const DRIFT: usize = 2;

/// All material points, one vector per field.
#[derive(Clone, Debug, Default)]
pub struct Particles {
    /// Creation order; output is written in this order.
    pub id: Vec<u32>,
    /// Body index.
    pub body: Vec<u16>,
    /// Mass (kg per unit thickness).
    pub mass: Vec<f64>,
    /// Reference volume (m² per unit thickness).
    pub vol0: Vec<f64>,
    /// Position (m).
    pub pos: Vec<DVec2>,
    /// Initial position (m), for rotation diagnostics.
    pub pos0: Vec<DVec2>,
    /// Velocity (m/s).
    pub vel: Vec<DVec2>,
    /// Deformation gradient (in plane; F_zz = 1).
    pub def: Vec<DMat2>,
    /// Cauchy stress.
    pub stress: Vec<Stress>,
    /// Equivalent plastic strain ε̄ᵖ (J2 bodies; 0 elsewhere).
    pub plastic: Vec<f64>,
    /// Energy dissipated by plastic work and viscosity (J per unit thickness).
    pub dissipated: Vec<f64>,
    /// Work done by the point's thermal strain, −∫ tr σ α dT V (J per unit thickness).
    pub thermal_work: Vec<f64>,
    /// Interfacial bond strength (Pa) the point carries; lowered, and remembered, where
    /// the bonded interface fails. See [`crate::bond`].
    pub bond: Vec<f64>,
    /// Maxwell branch deviatoric stresses (xx, yy, xy), `branch_width` per point.
    pub branches: Vec<[f64; 3]>,
    /// Branches stored per point: the most any body's material needs (0 without Maxwell
    /// bodies). Set by [`Particles::set_branch_width`].
    pub branch_width: usize,
}

/// Where each body's points and each of its strips sit in the sorted arrays.
#[derive(Clone, Debug, Default)]
pub struct Layout {
    /// Point range `[start, end)` of each body.
    pub bodies: Vec<(usize, usize)>,
    /// `(body, strip, start, end)` of every non-empty strip, in sorted order.
    pub strips: Vec<(u16, u32, usize, usize)>,
}

impl Particles {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// True if there are none.
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// Appends an unstressed point.
    pub fn push(&mut self, body: u16, mass: f64, vol0: f64, pos: DVec2, vel: DVec2) {
        self.id.push(self.pos.len() as u32);
        self.body.push(body);
        self.mass.push(mass);
        self.vol0.push(vol0);
        self.pos.push(pos);
        self.pos0.push(pos);
        self.vel.push(vel);
        self.def.push(DMat2::IDENTITY);
        self.stress.push(Stress::default());
        self.plastic.push(0.0);
        self.dissipated.push(0.0);
        self.thermal_work.push(0.0);
        self.bond.push(0.0);
        self.branches
            .extend(std::iter::repeat_n([0.0; 3], self.branch_width));
    }

    /// Stores `width` Maxwell branches per point. Existing branch stresses are kept
    /// (padded with zeros or cut) point by point.
    pub fn set_branch_width(&mut self, width: usize) {
        if width == self.branch_width && self.branches.len() == width * self.len() {
            return;
        }
        let old = self.branch_width;
        let mut b = vec![[0.0; 3]; width * self.len()];
        for i in 0..self.len() {
            for k in 0..width.min(old) {
                b[i * width + k] = self.branches.get(i * old + k).copied().unwrap_or_default();
            }
        }
        self.branches = b;
        self.branch_width = width;
    }

    /// Point `i`'s branch stresses.
    pub fn branches_of(&self, i: usize) -> &[[f64; 3]] {
        &self.branches[i * self.branch_width..][..self.branch_width]
    }

    /// The fields a stress update touches, for points `[start, end)`.
    pub fn material_view(&mut self, start: usize, end: usize) -> MaterialView<'_> {
        let w = self.branch_width;
        MaterialView {
            vol0: &self.vol0[start..end],
            def: &mut self.def[start..end],
            stress: &mut self.stress[start..end],
            plastic: &mut self.plastic[start..end],
            dissipated: &mut self.dissipated[start..end],
            thermal_work: &mut self.thermal_work[start..end],
            branches: &mut self.branches[start * w..end * w],
            width: w,
        }
    }

    /// Current volume V₀·det F.
    #[inline]
    pub fn volume(&self, i: usize) -> f64 {
        self.vol0[i] * self.def[i].determinant()
    }

    /// Sorts the points by (body, strip, column, row, id) and returns the layout.
    /// Deterministic: the key is unique.
    pub fn sort(&mut self, grid: &Grid, bodies: usize) -> Layout {
        let n = self.len();
        let key = |i: usize| {
            let [cx, cy] = grid.cell_of(self.pos[i]);
            (self.body[i], cx / STRIP, cx, cy, self.id[i])
        };
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_unstable_by_key(|&i| key(i));
        if order.iter().enumerate().any(|(k, &i)| k != i) {
            fn permute<T: Copy>(v: &mut Vec<T>, order: &[usize]) {
                *v = order.iter().map(|&i| v[i]).collect();
            }
            permute(&mut self.id, &order);
            permute(&mut self.body, &order);
            permute(&mut self.mass, &order);
            permute(&mut self.vol0, &order);
            permute(&mut self.pos, &order);
            permute(&mut self.pos0, &order);
            permute(&mut self.vel, &order);
            permute(&mut self.def, &order);
            permute(&mut self.stress, &order);
            permute(&mut self.plastic, &order);
            permute(&mut self.dissipated, &order);
            permute(&mut self.thermal_work, &order);
            permute(&mut self.bond, &order);
            let w = self.branch_width;
            if w > 0 {
                self.branches = order
                    .iter()
                    .flat_map(|&i| self.branches[i * w..(i + 1) * w].iter().copied())
                    .collect();
            }
        }
        let mut layout = Layout {
            bodies: vec![(0, 0); bodies],
            strips: Vec::new(),
        };
        let mut k = 0;
        while k < n {
            let b = self.body[k];
            let s = grid.cell_of(self.pos[k])[0] / STRIP;
            let start = k;
            while k < n && self.body[k] == b && grid.cell_of(self.pos[k])[0] / STRIP == s {
                k += 1;
            }
            layout.strips.push((b, s as u32, start, k));
        }
        for b in 0..bodies {
            let start = self.body.partition_point(|&x| (x as usize) < b);
            let end = self.body.partition_point(|&x| (x as usize) <= b);
            layout.bodies[b] = (start, end);
        }
        layout
    }
}

/// Stored node columns `[lo, hi)` a strip's points may touch, drift included.
pub fn strip_columns(strip: usize) -> (usize, usize) {
    // Cells [sW − D, (s+1)W + D) reach nodes [cell − 1, cell + 2]; stored = node + GHOST.
    let lo = (strip * STRIP + crate::grid::GHOST).saturating_sub(DRIFT + 1);
    let hi = (strip + 1) * STRIP + DRIFT + 2 + crate::grid::GHOST;
    (lo, hi)
}

/// True if a point now in cell column `cx` may stay assigned to `strip`.
#[inline]
pub fn within_strip(cx: usize, strip: usize) -> bool {
    cx + DRIFT >= strip * STRIP && cx < (strip + 1) * STRIP + DRIFT
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_colour_strips_are_disjoint() {
        const { assert!(STRIP >= 2 * DRIFT + 3) };
        for s in 0..10 {
            let (_, hi) = strip_columns(s);
            let (lo2, _) = strip_columns(s + 2);
            assert!(hi <= lo2, "strip {s}: {hi} > {lo2}");
        }
    }

    #[test]
    fn sort_groups_bodies_and_strips() {
        let grid = Grid {
            lo: DVec2::ZERO,
            h: 1.0,
            cells: [40, 4],
            periodic_y: false,
        };
        let mut p = Particles::default();
        for k in 0..40 {
            let x = (k * 7 % 40) as f64 + 0.5;
            p.push((k % 2) as u16, 1.0, 1.0, DVec2::new(x, 1.5), DVec2::ZERO);
        }
        let layout = p.sort(&grid, 2);
        assert_eq!(layout.bodies, vec![(0, 20), (20, 40)]);
        assert_eq!(layout.strips.len(), 10);
        for &(b, s, start, end) in &layout.strips {
            for i in start..end {
                assert_eq!(p.body[i], b);
                assert_eq!(grid.cell_of(p.pos[i])[0] / STRIP, s as usize);
            }
        }
    }
}
