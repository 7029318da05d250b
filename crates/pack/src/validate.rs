//! Checks a spec before anything is computed or written: every bad value is a
//! one-line error naming the key, the value and what is allowed.

use crate::sizes::Distribution;
use crate::spec::{DomainSpec, PackSpec, SizeSpec};
use glam::DVec2;
use grains_analysis::region::Region;
use grains_core::input::{InputError, Shown};

fn err(key: &str, value: impl Shown, allowed: impl Into<String>) -> InputError {
    InputError::new(key, value, allowed)
}

/// Largest number of disks a spec may ask for (memory and time guard).
pub const MAX_PARTICLES: f64 = 2.0e7;
/// Densest packing of equal disks, π/(2√3); no target above 0.9 is reachable with
/// the distributions offered.
pub const MAX_TARGET: f64 = 0.90;

/// Figures a `[[check]]` may bound.
pub const CHECKABLE: [&str; 10] = [
    "particles",
    "mean_diameter",
    "polydispersity",
    "packing_fraction_bulk",
    "psi6_local_mean_all",
    "psi6_local_mean_interior",
    "psi6_global_all",
    "psi6_global_interior",
    "mean_coordination",
    "fabric_anisotropy",
];

/// A spec that passed validation, with what follows from it.
#[derive(Clone, Debug)]
pub struct Validated {
    /// The container (SI).
    pub region: Region,
    /// The bulk size distribution (SI diameters).
    pub sizes: Distribution,
    /// Nominal mean diameter (m).
    pub d0: f64,
    /// Lining disk diameter (m), before fitting a whole number around each wall.
    pub lining_diameter: f64,
    /// Expected number of bulk disks at the target fraction.
    pub estimated_particles: f64,
}

fn finite_positive(key: &str, v: f64) -> Result<(), InputError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(err(key, v, "must be a finite number > 0"))
    }
}

fn in_range(key: &str, v: f64, lo: f64, hi: f64, what: &str) -> Result<(), InputError> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err(err(key, v, format!("must be in [{lo}, {hi}]{what}")))
    }
}

/// Validates a spec.
pub fn validate(spec: &PackSpec) -> Result<Validated, InputError> {
    grains_core::input::file_name("name", &spec.name)?;
    let (d0, d_max) = sizes(&spec.sizes)?;
    let dist = Distribution::from_spec(&spec.sizes);
    let p = &spec.protocol;
    if !(p.target_fraction.is_finite()
        && p.target_fraction > 0.0
        && p.target_fraction <= MAX_TARGET)
    {
        return Err(err(
            "protocol.target_fraction",
            p.target_fraction,
            "must be in (0, 0.9]: denser is unreachable (equal disks top out at π/(2√3) = 0.9069)",
        ));
    }
    if !(p.rate.is_finite() && p.rate > 0.0 && p.rate <= 0.01) {
        return Err(err(
            "protocol.rate",
            p.rate,
            "must be in (0, 0.01] (relative radius growth per sweep)",
        ));
    }
    // A sorted lattice holds its order up to a dense start; any other start disorders
    // (or cannot be placed) above 0.8.
    let top = if p.sort_sweeps > 0 { 0.88 } else { 0.8 };
    if !(p.start_fraction.is_finite() && (0.3..=top).contains(&p.start_fraction)) {
        return Err(err(
            "protocol.start_fraction",
            p.start_fraction,
            format!("must be in [0.3, {top}] (up to 0.88 with protocol.sort_sweeps > 0)"),
        ));
    }
    if p.finish == crate::spec::FinishSpec::Target && p.start_fraction >= p.target_fraction {
        return Err(err(
            "protocol.start_fraction",
            p.start_fraction,
            format!(
                "must be below protocol.target_fraction = {} when protocol.finish = \"target\" (the growth ends there)",
                p.target_fraction
            ),
        ));
    }
    if p.anneal_sweeps > 10_000_000 {
        return Err(err(
            "protocol.anneal_sweeps",
            p.anneal_sweeps,
            "must be at most 10000000",
        ));
    }
    if p.sort_sweeps > 100_000 {
        return Err(err(
            "protocol.sort_sweeps",
            p.sort_sweeps,
            "must be at most 100000",
        ));
    }
    if p.sort_sweeps > 0 && p.start != crate::spec::StartSpec::Lattice {
        return Err(err(
            "protocol.sort_sweeps",
            p.sort_sweeps,
            "sorts sizes on lattice sites: it needs protocol.start = \"lattice\" (or 0)",
        ));
    }
    if p.max_sweeps > 10_000_000 {
        return Err(err(
            "protocol.max_sweeps",
            p.max_sweeps,
            "must be at most 10000000",
        ));
    }
    if !(p.swell_step.is_finite() && p.swell_step > 0.0 && p.swell_step <= 0.05) {
        return Err(err(
            "protocol.swell_step",
            p.swell_step,
            "must be in (0, 0.05]",
        ));
    }
    in_range("protocol.max_swell", p.max_swell, 0.0, 0.5, "")?;
    in_range("protocol.deposit_scale", p.deposit_scale, 0.5, 1.0, "")?;
    let ratio = spec.lining.diameter_ratio;
    if !(ratio.is_finite() && (0.2..=1.0).contains(&ratio)) {
        return Err(err(
            "lining.diameter_ratio",
            ratio,
            "must be in [0.2, 1] (lining diameter over d0)",
        ));
    }
    let lining = ratio * d0;
    // Room for one bulk disk of the largest likely size between two lining layers.
    let need = 2.0 * lining + d_max;
    let region = match spec.domain {
        DomainSpec::Annulus {
            r_in,
            r_out,
            centre,
        } => {
            finite_positive("domain.r_in", r_in)?;
            finite_positive("domain.r_out", r_out)?;
            if r_out <= r_in {
                return Err(err(
                    "domain.r_out",
                    r_out,
                    format!("must be greater than domain.r_in = {r_in}"),
                ));
            }
            if r_out - r_in < need {
                return Err(err(
                    "domain.r_out",
                    r_out,
                    format!("the ring is too narrow for one disk between the linings: r_out − r_in must be at least {need:.4e} m"),
                ));
            }
            if r_in < lining {
                return Err(err(
                    "domain.r_in",
                    r_in,
                    format!("must be at least one lining diameter ({lining:.4e} m)"),
                ));
            }
            Region::Annulus {
                centre: point("domain.centre", centre)?,
                r_in,
                r_out,
            }
        }
        DomainSpec::Disk { radius, centre } => {
            finite_positive("domain.radius", radius)?;
            if 2.0 * radius < need {
                return Err(err(
                    "domain.radius",
                    radius,
                    format!(
                        "too small for one disk inside the lining: must be at least {:.4e} m",
                        need / 2.0
                    ),
                ));
            }
            Region::Disk {
                centre: point("domain.centre", centre)?,
                radius,
            }
        }
        DomainSpec::Rectangle {
            width,
            height,
            periodic_x,
        } => {
            finite_positive("domain.width", width)?;
            finite_positive("domain.height", height)?;
            if height < need {
                return Err(err(
                    "domain.height",
                    height,
                    format!(
                        "too small for one disk between the linings: must be at least {need:.4e} m"
                    ),
                ));
            }
            let min_w = if periodic_x { 3.0 * d_max } else { need };
            if width < min_w {
                return Err(err(
                    "domain.width",
                    width,
                    format!("too small: must be at least {min_w:.4e} m"),
                ));
            }
            Region::Rectangle {
                lo: DVec2::ZERO,
                hi: DVec2::new(width, height),
                periodic_x,
            }
        }
    };
    for (k, c) in spec.checks.iter().enumerate() {
        let key = format!("check[{k}].figure");
        if !CHECKABLE.contains(&c.figure.as_str()) {
            return Err(err(
                &key,
                format!("{:?}", c.figure),
                format!("must be one of {}", CHECKABLE.join(", ")),
            ));
        }
        match (c.at_least, c.at_most) {
            (Some(v), None) | (None, Some(v)) if v.is_finite() => {}
            _ => {
                return Err(err(
                    &format!("check[{k}]"),
                    format!("at_least = {:?}, at_most = {:?}", c.at_least, c.at_most),
                    "give exactly one finite bound, at_least or at_most",
                ))
            }
        }
    }
    let disk_area = std::f64::consts::FRAC_PI_4 * dist.mean_square();
    let estimated = region.area() * p.target_fraction / disk_area;
    if estimated > MAX_PARTICLES {
        return Err(err(
            "sizes.d0",
            d0,
            format!("would need about {estimated:.3e} disks; at most {MAX_PARTICLES:e} are supported: use larger disks or a smaller domain"),
        ));
    }
    Ok(Validated {
        region,
        sizes: dist,
        d0,
        lining_diameter: lining,
        estimated_particles: estimated,
    })
}

fn point(key: &str, p: [f64; 2]) -> Result<DVec2, InputError> {
    if p.iter().all(|v| v.is_finite()) {
        Ok(DVec2::new(p[0], p[1]))
    } else {
        Err(err(
            key,
            format!("[{}, {}]", p[0], p[1]),
            "must be two finite numbers",
        ))
    }
}

/// Nominal mean diameter and a likely largest diameter of the size spec.
fn sizes(s: &SizeSpec) -> Result<(f64, f64), InputError> {
    match *s {
        SizeSpec::Gaussian { d0, delta } => {
            finite_positive("sizes.d0", d0)?;
            if !(delta.is_finite() && (0.0..=0.4).contains(&delta)) {
                return Err(err("sizes.delta", delta, "must be in [0, 0.4] for a Gaussian (above, truncation at d ≤ 0 removes more than 0.6 % and skews it)"));
            }
            Ok((d0, d0 * (1.0 + 4.0 * delta)))
        }
        SizeSpec::Uniform { d0, delta } => {
            finite_positive("sizes.d0", d0)?;
            let limit = 1.0 / 3f64.sqrt();
            if !(delta.is_finite() && delta >= 0.0 && delta < limit) {
                return Err(err("sizes.delta", delta, "must be in [0, 1/√3 = 0.577) for a uniform distribution (at 1/√3 the smallest diameter reaches 0)"));
            }
            Ok((d0, d0 * (1.0 + 3f64.sqrt() * delta)))
        }
        SizeSpec::Lognormal { d0, delta } => {
            finite_positive("sizes.d0", d0)?;
            if !(delta.is_finite() && delta > 0.0 && delta <= 1.0) {
                return Err(err(
                    "sizes.delta",
                    delta,
                    "must be in (0, 1] for a log-normal distribution",
                ));
            }
            let s = (1.0 + delta * delta).ln().sqrt();
            Ok((d0, d0 * (3.0 * s).exp()))
        }
        SizeSpec::Bidisperse {
            d_small,
            d_large,
            fraction_large,
        } => {
            finite_positive("sizes.d_small", d_small)?;
            finite_positive("sizes.d_large", d_large)?;
            if d_large < d_small {
                return Err(err(
                    "sizes.d_large",
                    d_large,
                    format!("must be at least sizes.d_small = {d_small}"),
                ));
            }
            if d_large > 10.0 * d_small {
                return Err(err(
                    "sizes.d_large",
                    d_large,
                    "must be at most 10 × sizes.d_small",
                ));
            }
            in_range(
                "sizes.fraction_large",
                fraction_large,
                0.0,
                1.0,
                " (number fraction)",
            )?;
            Ok((d_small + fraction_large * (d_large - d_small), d_large))
        }
    }
}
