//! Axis ranges and tick labels that stay sane for any data.

/// Magnitudes beyond this are dropped from plots: an axis spanning them
/// would overflow `hi - lo`, and such values only appear in blown-up runs.
pub(crate) const MAX_ABS: f64 = 1e300;

/// Below this a span or magnitude is treated as zero, for the same reason
/// at the other end of the exponent range.
const MIN_SPAN: f64 = 1e-290;

/// True if `v` can be placed on an axis.
pub(crate) fn plottable(v: f64) -> bool {
    v.is_finite() && v.abs() <= MAX_ABS
}

/// Min and max of the plottable values, or `None` if there are none.
pub(crate) fn extent(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    values
        .into_iter()
        .filter(|v| plottable(*v))
        .fold(None, |acc, v| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
        })
}

/// An axis range around `extent` with `margin` (a fraction of the span) on
/// both sides. A missing or degenerate extent gets a range around its value
/// instead, since plotters cannot map an empty interval.
pub(crate) fn axis_range(extent: Option<(f64, f64)>, margin: f64) -> (f64, f64) {
    let Some((lo, hi)) = extent else {
        return (0.0, 1.0);
    };
    let span = hi - lo;
    let scale = lo.abs().max(hi.abs());
    if span <= MIN_SPAN || span <= 1e-12 * scale {
        let c = 0.5 * (lo + hi);
        let half = if c.abs() > MIN_SPAN {
            0.05 * c.abs()
        } else {
            1.0
        };
        return (c - half, c + half);
    }
    (lo - margin * span, hi + margin * span)
}

/// Tick label for `v` on a linear axis spanning `lo..hi`: fixed notation
/// for everyday magnitudes, scientific (`2.5e-7`) for very small or large
/// ones, with the fewest digits that still pin the tick down (ticks sit on
/// round numbers, so this drops the noise of floating-point tick values).
pub(crate) fn format_linear(v: f64, lo: f64, hi: f64) -> String {
    let span = (hi - lo).abs();
    if span.is_nan() || span <= 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    // Far below any plausible tick spacing, far above float noise.
    let tol = span * 1e-5;
    if v.abs() < tol {
        return "0".to_string();
    }
    let scale = lo.abs().max(hi.abs());
    let close = |s: &str| s.parse::<f64>().is_ok_and(|p| (p - v).abs() <= tol);
    if (1e-3..1e5).contains(&scale) {
        (0..=12)
            .map(|d| format!("{v:.d$}"))
            .find(|s| close(s))
            .unwrap_or_else(|| format!("{v}"))
    } else {
        (0..=12)
            .map(|d| format!("{v:.d$e}"))
            .find(|s| close(s))
            .unwrap_or_else(|| format!("{v:e}"))
    }
}

/// Tick label for the exponent `e` of a log axis, i.e. for the value `10^e`.
pub(crate) fn format_pow10(e: f64) -> String {
    if !e.is_finite() {
        return String::new();
    }
    let v = 10f64.powf(e);
    let whole = (e - e.round()).abs() < 1e-9;
    if whole {
        let k = e.round() as i32;
        // Built as text: 10f64.powi(-2) prints as 0.010000000000000002.
        return match k {
            0..=4 => format!("1{}", "0".repeat(k as usize)),
            -3..=-1 => format!("0.{}1", "0".repeat((-k - 1) as usize)),
            _ => format!("1e{k}"),
        };
    }
    if (1e-3..1e5).contains(&v) {
        let decimals = (2.0 - v.log10().floor()).max(0.0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.2e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extent_skips_non_finite() {
        let v = [f64::NAN, 2.0, f64::INFINITY, -1.0, 1e308];
        assert_eq!(extent(v), Some((-1.0, 2.0)));
        assert_eq!(extent([f64::NAN]), None);
        assert_eq!(extent(std::iter::empty()), None);
    }

    #[test]
    fn degenerate_ranges_are_padded() {
        assert_eq!(axis_range(None, 0.05), (0.0, 1.0));
        assert_eq!(axis_range(Some((0.0, 0.0)), 0.05), (-1.0, 1.0));
        let (lo, hi) = axis_range(Some((5.0, 5.0)), 0.05);
        assert!(lo < 5.0 && hi > 5.0);
        let (lo, hi) = axis_range(Some((-1e-7, -1e-7)), 0.05);
        assert!(lo < -1e-7 && hi > -1e-7 && hi < 0.0);
        let (lo, hi) = axis_range(Some((1.0, 1.0 + 1e-15)), 0.05);
        assert!(hi - lo > 0.01);
        assert_eq!(axis_range(Some((0.0, 10.0)), 0.1), (-1.0, 11.0));
        let (lo, hi) = axis_range(Some((-1e300, 1e300)), 0.05);
        assert!(lo.is_finite() && hi.is_finite());
    }

    #[test]
    fn linear_labels() {
        assert_eq!(format_linear(0.5, 0.0, 1.0), "0.5");
        assert_eq!(format_linear(20.0, 0.0, 100.0), "20");
        assert_eq!(format_linear(0.1 + 0.2, 0.0, 1.0), "0.3");
        assert_eq!(format_linear(0.025, 0.0, 0.1), "0.025");
        assert_eq!(format_linear(2e-7, 0.0, 1e-6), "2e-7");
        assert_eq!(format_linear(1.5e-7, 0.0, 1e-6), "1.5e-7");
        assert_eq!(format_linear(1.5e9, 1e9, 2e9), "1.5e9");
        assert_eq!(format_linear(-2.5e9, -3e9, 2e9), "-2.5e9");
        assert_eq!(format_linear(1e-17, -1.0, 1.0), "0");
        assert_eq!(format_linear(3.0, 3.0, 3.0), "3");
    }

    #[test]
    fn log_labels() {
        assert_eq!(format_pow10(0.0), "1");
        assert_eq!(format_pow10(-2.0), "0.01");
        assert_eq!(format_pow10(-7.0), "1e-7");
        assert_eq!(format_pow10(12.0), "1e12");
        assert_eq!(format_pow10(0.5), "3.16");
        assert_eq!(format_pow10(-6.5), "3.16e-7");
        assert_eq!(format_pow10(f64::NAN), "");
    }
}
