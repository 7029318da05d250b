//! A perceptually ordered colour map for particle maps.

use plotters::style::RGBColor;

/// Control points of a viridis-like ramp (dark purple → blue → teal →
/// green → yellow), interpolated linearly in RGB. Five points are enough for
/// a readable monotone-lightness map without carrying a 256-entry table.
const STOPS: [(f64, [f64; 3]); 5] = [
    (0.00, [68.0, 1.0, 84.0]),
    (0.25, [59.0, 82.0, 139.0]),
    (0.50, [33.0, 145.0, 140.0]),
    (0.75, [94.0, 201.0, 98.0]),
    (1.00, [253.0, 231.0, 37.0]),
];

/// Colour for `t` in `[0, 1]` (clamped; NaN gives mid grey, so missing
/// values stand out from the ramp).
pub fn viridis(t: f64) -> RGBColor {
    if t.is_nan() {
        return RGBColor(160, 160, 160);
    }
    let t = t.clamp(0.0, 1.0);
    let mut k = 1;
    while k < STOPS.len() - 1 && t > STOPS[k].0 {
        k += 1;
    }
    let (t0, c0) = STOPS[k - 1];
    let (t1, c1) = STOPS[k];
    let f = (t - t0) / (t1 - t0);
    let ch = |i: usize| (c0[i] + f * (c1[i] - c0[i])).round() as u8;
    RGBColor(ch(0), ch(1), ch(2))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn endpoints_clamping_and_nan() {
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
        assert_eq!(viridis(-3.0), viridis(0.0));
        assert_eq!(viridis(7.0), viridis(1.0));
        assert_eq!(viridis(0.5), RGBColor(33, 145, 140));
        assert_eq!(viridis(f64::NAN), RGBColor(160, 160, 160));
    }

    #[test]
    fn lightness_increases() {
        let luma = |c: RGBColor| 0.299 * c.0 as f64 + 0.587 * c.1 as f64 + 0.114 * c.2 as f64;
        let mut last = -1.0;
        for i in 0..=100 {
            let l = luma(viridis(i as f64 / 100.0));
            assert!(l >= last, "{i}");
            last = l;
        }
    }
}
