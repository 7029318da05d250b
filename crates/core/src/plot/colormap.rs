//! Colour maps: a perceptually ordered sequential ramp (viridis-like) for magnitudes and
//! a diverging blue–white–red ramp for signed fields centred on zero.

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
    ramp(&STOPS, t)
}

/// Control points of a diverging ramp (after Moreland's cool–warm): saturated blue at
/// 0, white at ½, saturated red at 1, so the sign of a field centred on zero reads at a
/// glance and its magnitude as saturation.
const DIVERGING: [(f64, [f64; 3]); 5] = [
    (0.00, [33.0, 102.0, 172.0]),
    (0.25, [146.0, 197.0, 222.0]),
    (0.50, [247.0, 247.0, 247.0]),
    (0.75, [244.0, 165.0, 130.0]),
    (1.00, [178.0, 24.0, 43.0]),
];

/// Colour for `t` in `[0, 1]` on the piecewise-linear ramp through `stops` (clamped;
/// NaN gives mid grey, so missing values stand out from the ramp).
fn ramp(stops: &[(f64, [f64; 3])], t: f64) -> RGBColor {
    if t.is_nan() {
        return RGBColor(160, 160, 160);
    }
    let t = t.clamp(0.0, 1.0);
    let mut k = 1;
    while k < stops.len() - 1 && t > stops[k].0 {
        k += 1;
    }
    let (t0, c0) = stops[k - 1];
    let (t1, c1) = stops[k];
    let f = (t - t0) / (t1 - t0);
    let ch = |i: usize| (c0[i] + f * (c1[i] - c0[i])).round() as u8;
    RGBColor(ch(0), ch(1), ch(2))
}

/// Colour for `t` in `[0, 1]` on the diverging ramp, white at ½ (clamped; NaN gives
/// mid grey).
pub fn diverging(t: f64) -> RGBColor {
    ramp(&DIVERGING, t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diverging_is_white_in_the_middle_and_symmetric_in_lightness() {
        assert_eq!(diverging(0.5), RGBColor(247, 247, 247));
        assert_eq!(diverging(-1.0), diverging(0.0));
        let luma = |c: RGBColor| 0.299 * c.0 as f64 + 0.587 * c.1 as f64 + 0.114 * c.2 as f64;
        for i in 0..50 {
            let t = i as f64 / 100.0;
            assert!(luma(diverging(t)) <= luma(diverging(t + 0.01)) + 1.0, "{t}");
            assert!(
                luma(diverging(1.0 - t)) <= luma(diverging(0.99 - t)) + 1.0,
                "{t}"
            );
        }
    }

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
