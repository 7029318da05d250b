//! Triangle mesh of a circular charge, refined toward its edge (xue-2019 Fig. 4).
//!
//! Nodes sit on concentric rings. Going inward from the edge, the local size grows
//! linearly from `size_edge` by `grading` per unit distance until it reaches
//! `size_centre`; each ring is one local size (times √3/2, the height of an equilateral
//! triangle) inside the previous one, and holds as many nodes as its circumference takes
//! at that size. Neighbouring rings are zipped into triangles by walking both rings by
//! angle, and a single node closes the centre. The outermost ring lies exactly on the
//! circle, so the boundary follows it to within the sagitta R(1 − cos(π/n)).

use glam::DVec2;
use grains_core::input::{positive, shown, InputError};
use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, TAU};

/// How the charge is meshed (lengths in m).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    /// Element size at the centre.
    pub size_centre: f64,
    /// Element size at the edge.
    pub size_edge: f64,
    /// Growth of the element size per unit distance inward from the edge.
    #[serde(default = "default_grading")]
    pub grading: f64,
}

fn default_grading() -> f64 {
    0.25
}

/// Fewest elements across the radius, and most relative size of an edge element, for
/// the mesh to resolve a charge: below these the polygon misses the circle's area by
/// more than ~0.2 % and the detonation front spans a large part of the radius.
pub const MIN_ELEMENTS_ACROSS: f64 = 10.0;

/// A triangle mesh with its boundary.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Node positions (m).
    pub nodes: Vec<DVec2>,
    /// Triangles, counter-clockwise.
    pub tris: Vec<[u32; 3]>,
    /// Boundary edges, counter-clockwise around the charge (outward normal on the right).
    pub boundary: Vec<[u32; 2]>,
}

/// Signed area of triangle (a, b, c), positive when counter-clockwise.
#[inline]
pub fn signed_area(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    0.5 * (b - a).perp_dot(c - a)
}

impl Mesh {
    /// Total area (m² per unit thickness).
    pub fn area(&self) -> f64 {
        self.tris
            .iter()
            .map(|t| {
                signed_area(
                    self.nodes[t[0] as usize],
                    self.nodes[t[1] as usize],
                    self.nodes[t[2] as usize],
                )
            })
            .sum()
    }

    /// Smallest and largest edge length of any triangle.
    pub fn edge_range(&self) -> (f64, f64) {
        let mut lo = f64::INFINITY;
        let mut hi: f64 = 0.0;
        for t in &self.tris {
            for k in 0..3 {
                let l = (self.nodes[t[(k + 1) % 3] as usize] - self.nodes[t[k] as usize]).length();
                lo = lo.min(l);
                hi = hi.max(l);
            }
        }
        (lo, hi)
    }

    /// Smallest angle of any triangle (rad), the usual quality figure.
    pub fn min_angle(&self) -> f64 {
        let mut m = PI;
        for t in &self.tris {
            let p = t.map(|i| self.nodes[i as usize]);
            for k in 0..3 {
                let (a, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
                m = m.min((b - a).angle_to(c - a).abs());
            }
        }
        m
    }
}

/// Meshes the disk of `radius` about `centre`; refuses sizes that cannot resolve it.
pub fn circle(radius: f64, centre: DVec2, spec: &MeshSpec) -> Result<Mesh, InputError> {
    positive("charge.radius", radius)?;
    positive("charge.mesh.size_edge", spec.size_edge)?;
    positive("charge.mesh.size_centre", spec.size_centre)?;
    if !(spec.grading.is_finite() && spec.grading >= 0.0) {
        return Err(InputError::new(
            "charge.mesh.grading",
            shown(spec.grading),
            "must be a finite number >= 0",
        ));
    }
    let coarsest = radius / MIN_ELEMENTS_ACROSS;
    if spec.size_edge > coarsest {
        return Err(InputError::new(
            "charge.mesh.size_edge",
            shown(spec.size_edge),
            format!(
                "too coarse to resolve a charge of radius {} m: at most radius/{MIN_ELEMENTS_ACROSS} = {} m",
                shown(radius),
                shown(coarsest)
            ),
        ));
    }
    if spec.size_centre > 3.0 * coarsest {
        return Err(InputError::new(
            "charge.mesh.size_centre",
            shown(spec.size_centre),
            format!(
                "too coarse: at most 3 × radius/{MIN_ELEMENTS_ACROSS} = {} m",
                shown(3.0 * coarsest)
            ),
        ));
    }
    if spec.size_centre < spec.size_edge {
        return Err(InputError::new(
            "charge.mesh.size_centre",
            shown(spec.size_centre),
            format!(
                "must be >= size_edge = {} m (the mesh is refined toward the edge)",
                shown(spec.size_edge)
            ),
        ));
    }
    if radius / spec.size_edge > 20_000.0 {
        return Err(InputError::new(
            "charge.mesh.size_edge",
            shown(spec.size_edge),
            "too fine: more than 20000 elements across the radius",
        ));
    }
    let size = |r: f64| (spec.size_edge + spec.grading * (radius - r)).min(spec.size_centre);

    // Ring radii from the edge inward; stop once the next ring would crowd the centre.
    let mut radii = vec![radius];
    loop {
        let r = *radii.last().unwrap();
        let next = r - size(r) * 0.5 * 3f64.sqrt();
        if next < 0.6 * size(next.max(0.0)) {
            break;
        }
        radii.push(next);
    }
    radii.reverse();
    let mut mesh = Mesh::default();
    mesh.nodes.push(centre);
    let mut rings: Vec<(u32, usize, f64)> = Vec::new(); // (first node, count, angle offset)
    for (k, &r) in radii.iter().enumerate() {
        let n = ((TAU * r / size(r)).round() as usize).max(6);
        let offset = if k % 2 == 1 { 0.5 / n as f64 } else { 0.0 };
        let first = mesh.nodes.len() as u32;
        for i in 0..n {
            let a = TAU * (i as f64 / n as f64 + offset);
            mesh.nodes.push(centre + r * DVec2::new(a.cos(), a.sin()));
        }
        rings.push((first, n, offset));
    }
    // Centre fan.
    let (f0, n0, _) = rings[0];
    for i in 0..n0 {
        push_ccw(&mut mesh, [0, f0 + i as u32, f0 + ((i + 1) % n0) as u32]);
    }
    // Zip ring k to ring k+1 by angle.
    for w in rings.windows(2) {
        let (fa, na, oa) = w[0];
        let (fb, nb, ob) = w[1];
        let pos_a = |i: usize| i as f64 / na as f64 + oa;
        let pos_b = |j: usize| j as f64 / nb as f64 + ob;
        let (mut i, mut j) = (0usize, 0usize);
        while i < na || j < nb {
            let node_a = |i: usize| fa + (i % na) as u32;
            let node_b = |j: usize| fb + (j % nb) as u32;
            let advance_a = j >= nb || (i < na && pos_a(i + 1) < pos_b(j + 1));
            if advance_a {
                push_ccw(&mut mesh, [node_a(i), node_a(i + 1), node_b(j)]);
                i += 1;
            } else {
                push_ccw(&mut mesh, [node_a(i), node_b(j + 1), node_b(j)]);
                j += 1;
            }
        }
    }
    let (fb, nb, _) = *rings.last().unwrap();
    for j in 0..nb {
        mesh.boundary
            .push([fb + j as u32, fb + ((j + 1) % nb) as u32]);
    }
    Ok(mesh)
}

fn push_ccw(mesh: &mut Mesh, t: [u32; 3]) {
    let p = t.map(|i| mesh.nodes[i as usize]);
    if signed_area(p[0], p[1], p[2]) >= 0.0 {
        mesh.tris.push(t);
    } else {
        mesh.tris.push([t[0], t[2], t[1]]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(centre: f64, edge: f64) -> MeshSpec {
        MeshSpec {
            size_centre: centre,
            size_edge: edge,
            grading: 0.25,
        }
    }

    #[test]
    fn covers_the_disk_with_positive_well_shaped_triangles() {
        let r = 0.01;
        let m = circle(r, DVec2::new(0.002, -0.001), &spec(0.6e-3, 0.2e-3)).unwrap();
        let exact = PI * r * r;
        assert!(
            (m.area() - exact).abs() < 2e-3 * exact,
            "area {} vs {exact}",
            m.area()
        );
        for t in &m.tris {
            let p = t.map(|i| m.nodes[i as usize]);
            assert!(signed_area(p[0], p[1], p[2]) > 0.0);
        }
        assert!(
            m.min_angle() > 20f64.to_radians(),
            "min angle {}",
            m.min_angle().to_degrees()
        );
        // Every boundary node lies on the circle; the boundary closes.
        let mut len = 0.0;
        for e in &m.boundary {
            let (a, b) = (m.nodes[e[0] as usize], m.nodes[e[1] as usize]);
            assert!(((a - DVec2::new(0.002, -0.001)).length() - r).abs() < 1e-12);
            len += (b - a).length();
        }
        assert!((len - TAU * r).abs() < 1e-3 * TAU * r);
        // Refined toward the edge.
        let edge =
            (m.nodes[m.boundary[0][1] as usize] - m.nodes[m.boundary[0][0] as usize]).length();
        assert!((edge - 0.2e-3).abs() < 0.02e-3, "edge size {edge}");
        // Each interior edge is shared by two triangles, each boundary edge by one.
        let mut count = std::collections::HashMap::new();
        for t in &m.tris {
            for k in 0..3 {
                let (a, b) = (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]));
                *count.entry((a, b)).or_insert(0) += 1;
            }
        }
        let once = count.values().filter(|&&c| c == 1).count();
        assert_eq!(once, m.boundary.len());
        assert!(count.values().all(|&c| c <= 2));
    }

    #[test]
    fn coarse_meshes_are_refused() {
        let e = circle(0.01, DVec2::ZERO, &spec(3e-3, 2e-3)).unwrap_err();
        assert_eq!(e.key, "charge.mesh.size_edge");
        assert!(e.allowed.contains("too coarse"), "{e}");
        let e = circle(0.01, DVec2::ZERO, &spec(0.1e-3, 0.2e-3)).unwrap_err();
        assert_eq!(e.key, "charge.mesh.size_centre");
    }
}
