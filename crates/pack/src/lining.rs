//! The boundary layer: a chain of equal small disks tangent to each wall and to
//! their neighbours (xue-2019 §4.1: "about 0.6 d0"), so the bulk meets a smooth,
//! nearly circular surface instead of a wall it could order against.

use glam::DVec2;
use grains_analysis::region::Region;
use std::f64::consts::PI;

/// Lining disks as `(centre, radius)` for every wall of `region`, with diameters close
/// to `d`. `phase` (in [0, 1)) rotates each circular chain by a fraction of a pitch.
pub fn lining(region: &Region, d: f64, phase: f64) -> Vec<(DVec2, f64)> {
    let mut out = Vec::new();
    match *region {
        Region::Annulus {
            centre,
            r_in,
            r_out,
        } => {
            ring(&mut out, centre, r_in, d, true, phase);
            ring(&mut out, centre, r_out, d, false, phase);
        }
        Region::Disk { centre, radius } => ring(&mut out, centre, radius, d, false, phase),
        Region::Rectangle { lo, hi, periodic_x } => {
            let w = hi.x - lo.x;
            // Floor and ceiling: touching chains; in periodic x they close on themselves.
            let m = ((w / d).floor() as usize).max(1);
            let pitch = w / m as f64;
            let a = if periodic_x {
                0.5 * pitch
            } else {
                0.5 * d.min(pitch)
            };
            let count = if periodic_x {
                m
            } else {
                ((w - 2.0 * a) / (2.0 * a)).floor() as usize + 1
            };
            let step = if periodic_x || count < 2 {
                pitch
            } else {
                (w - 2.0 * a) / (count - 1) as f64
            };
            for k in 0..count {
                let x = if periodic_x {
                    lo.x + (k as f64 + 0.5) * step
                } else {
                    lo.x + a + k as f64 * step
                };
                out.push((DVec2::new(x, lo.y + a), a));
                out.push((DVec2::new(x, hi.y - a), a));
            }
            if !periodic_x {
                // Side walls, between the floor and ceiling chains.
                let h = hi.y - lo.y - 4.0 * a;
                let n = (h / (2.0 * a)).floor() as usize;
                if n >= 1 {
                    let step = h / n as f64;
                    for k in 0..n {
                        let y = lo.y + 2.0 * a + (k as f64 + 0.5) * step;
                        out.push((DVec2::new(lo.x + a, y), a));
                        out.push((DVec2::new(hi.x - a, y), a));
                    }
                }
            }
        }
    }
    out
}

/// `m` equal touching disks tangent to a circle of radius `wall`, inside it (outer wall)
/// or outside it (`outside`, inner wall). The radius follows from `m` exactly:
/// a = R s / (1 ∓ s) with s = sin(π/m).
fn ring(out: &mut Vec<(DVec2, f64)>, centre: DVec2, wall: f64, d: f64, outside: bool, phase: f64) {
    let a0 = 0.5 * d;
    let rc = if outside { wall + a0 } else { wall - a0 };
    let m = ((PI / (a0 / rc).min(1.0).asin()).round() as usize).max(3);
    let s = (PI / m as f64).sin();
    let a = if outside {
        wall * s / (1.0 - s)
    } else {
        wall * s / (1.0 + s)
    };
    let rc = if outside { wall + a } else { wall - a };
    for k in 0..m {
        let t = 2.0 * PI * (k as f64 + phase) / m as f64;
        out.push((centre + rc * DVec2::from_angle(t), a));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn annulus_chains_touch_and_are_tangent() {
        let region = Region::Annulus {
            centre: DVec2::ZERO,
            r_in: 100.0,
            r_out: 140.0,
        };
        let l = lining(&region, 0.6, 0.3);
        for (c, a) in &l {
            assert!((a - 0.3).abs() < 0.01, "{a}");
            let gap = region.boundary_distance(*c) - a;
            assert!(gap.abs() < 1e-9, "{gap}");
        }
        // Neighbours in a chain touch.
        let inner: Vec<_> = l.iter().filter(|(c, _)| c.length() < 120.0).collect();
        let (c0, a0) = inner[0];
        let (c1, a1) = inner[1];
        assert!(((*c1 - *c0).length() - a0 - a1).abs() < 1e-9);
    }

    #[test]
    fn rectangle_lining_stays_inside() {
        for periodic_x in [false, true] {
            let region = Region::Rectangle {
                lo: DVec2::ZERO,
                hi: DVec2::new(20.0, 10.0),
                periodic_x,
            };
            for (c, a) in lining(&region, 0.6, 0.0) {
                assert!(region.boundary_distance(c) >= a - 1e-9);
            }
        }
    }
}
