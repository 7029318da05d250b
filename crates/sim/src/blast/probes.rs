//! The figures and checks of a finished blast run: detonation arrival and energy
//! conservation of the charge; ring-to-charge mass ratio, terminal band velocity and the
//! classic Gurney velocity of the ring.

use super::scenario::{CheckSpec, Scenario};
use grains_core::checks::Check;
use grains_core::history::History;
use grains_fem::diagnostics::{arrival_error, arrival_profile, energies, fronts, ArrivalBin};
use grains_fem::{Charge, FemSetup};
use serde_json::{Map, Value};

/// Radial range (in charge radii) and bins of the detonation-arrival check: the centre,
/// where a diverging front is still forming over its first few elements, is left out.
pub const ARRIVAL_RANGE: (f64, f64, usize) = (0.25, 0.95, 10);

/// What the evaluation reads.
pub struct Context<'a> {
    /// The scenario.
    pub scn: &'a Scenario,
    /// Charge settings.
    pub fem: &'a FemSetup,
    /// Final charge.
    pub charge: &'a Charge,
    /// Initial total energy of the charge (J/m).
    pub e0: f64,
    /// The run's history.
    pub history: &'a History,
    /// Charge mass (kg/m).
    pub charge_mass: f64,
    /// Ring mass (kg/m), if any.
    pub ring_mass: Option<f64>,
    /// The dispersal analysis's figures, if it ran.
    pub dispersal: Option<&'a Value>,
    /// The ring models (`figures.models`), if the run has a ring they describe.
    pub models: Option<&'a Value>,
}

/// The classic cylindrical Gurney velocity √(2E)·(M/C + ½)^(−½), with √(2E) from the
/// JWL energy E0/ρ0 (physics.md §2.1, the regression basis it recommends).
pub fn gurney_velocity(fem: &FemSetup, fill_to_burster: f64) -> f64 {
    gurney_constant(fem) / (fill_to_burster + 0.5).sqrt()
}

/// √(2E0/ρ0) (m/s).
pub fn gurney_constant(fem: &FemSetup) -> f64 {
    (2.0 * fem.explosive.specific_energy()).sqrt()
}

/// The paper's band velocity, if the scenario checks against one.
pub fn band_reference(scn: &Scenario) -> Option<f64> {
    scn.checks.iter().find_map(|c| match c {
        CheckSpec::BandVelocity { expected, .. } => Some(*expected),
        CheckSpec::BandVelocityBracket { paper } => Some(*paper),
        _ => None,
    })
}

/// Mean of column `name` over the rows in the last `window` of the run's time.
fn terminal(h: &History, name: &str, window: f64) -> f64 {
    let (Some(t), Some(v)) = (h.column("time"), h.column(name)) else {
        return f64::NAN;
    };
    let end = t.last().copied().unwrap_or(0.0);
    let from = end * (1.0 - window);
    let picked: Vec<f64> = t
        .iter()
        .zip(&v)
        .filter(|(t, v)| **t >= from && v.is_finite())
        .map(|(_, v)| *v)
        .collect();
    if picked.is_empty() {
        f64::NAN
    } else {
        picked.iter().sum::<f64>() / picked.len() as f64
    }
}

/// Checks, figures and the arrival profile.
pub fn evaluate(cx: &Context) -> (Vec<Check>, Map<String, Value>, Vec<ArrivalBin>) {
    let (fem, c) = (cx.fem, cx.charge);
    let r = cx.scn.charge.radius;
    let (lo, hi, bins) = ARRIVAL_RANGE;
    let arrival = arrival_profile(fem, c, lo * r, hi * r, bins);
    let (arrival_err, front_speed) = arrival_error(fem, &arrival);
    let e = energies(fem, c);
    let energy_err = e.balance(cx.e0).abs() / cx.e0;
    let f = fronts(c);
    let mut fig = Map::new();
    fig.insert("explosive".into(), fem.explosive.name.clone().into());
    fig.insert("charge_mass".into(), cx.charge_mass.into());
    fig.insert("burnt_fraction_final".into(), f.burnt.into());
    fig.insert("detonation_arrival_error".into(), arrival_err.into());
    fig.insert("detonation_front_speed".into(), front_speed.into());
    fig.insert("energy_conservation_error".into(), energy_err.into());
    fig.insert("gurney_constant".into(), gurney_constant(fem).into());
    let window = cx.scn.analysis.terminal_window;
    let mut fb = f64::NAN;
    let mut transfer_err = f64::NAN;
    if let Some(m) = cx.ring_mass {
        fb = m / cx.charge_mass;
        fig.insert("ring_mass".into(), m.into());
        fig.insert("fill_to_burster_ratio".into(), fb.into());
        fig.insert("gurney_velocity".into(), gurney_velocity(fem, fb).into());
        let h = cx.history;
        fig.insert(
            "band_velocity_terminal".into(),
            terminal(h, "band_velocity", window).into(),
        );
        fig.insert(
            "spall_velocity_terminal".into(),
            terminal(h, "spall_velocity", window).into(),
        );
        fig.insert(
            "band_fraction_final".into(),
            terminal(h, "band_fraction", window).into(),
        );
        fig.insert(
            "mean_radial_velocity_terminal".into(),
            terminal(h, "mean_radial_velocity", window).into(),
        );
        // Where the charge's work went: grains that collide inelastically or slide turn
        // the shock's random motion into heat, so the ring's kinetic energy falls short
        // of the work the gas did on it (the Gurney model assumes no such loss).
        let last = |name: &str| h.column(name).and_then(|c| c.last().copied());
        if let (Some(w), Some(ke)) = (last("work_on_charge"), last("particle_kinetic")) {
            let work = -w;
            fig.insert("work_on_ring".into(), work.into());
            fig.insert("ring_kinetic_energy".into(), ke.into());
            if work > 0.0 {
                fig.insert("ring_dissipated_fraction".into(), (1.0 - ke / work).into());
                transfer_err = (1.0 - ke / work).abs();
            }
        }
    }
    let mut checks = Vec::new();
    for spec in &cx.scn.checks {
        checks.push(match *spec {
            CheckSpec::DetonationArrival { tolerance } => Check::at_most("detonation_arrival_error", arrival_err, tolerance).with_note(&format!(
                "max over {bins} radial bins in [{lo}, {hi}]·R of |t − r/D_CJ|/(r/D_CJ); front = first time an element's \
                 pressure reaches P_CJ/2; fitted front speed {front_speed:.0} m/s vs D_CJ {:.0} m/s",
                fem.explosive.detonation_velocity
            )),
            CheckSpec::EnergyConservation { tolerance } => Check::at_most("energy_conservation_error", energy_err, tolerance).with_note(&format!(
                "|kinetic + internal + unreleased chemical − initial| / initial at the end; burnt fraction {:.4}",
                f.burnt
            )),
            CheckSpec::BandVelocity { expected, tolerance } => {
                let v = terminal(cx.history, "band_velocity", window);
                Check::relative("band_velocity_terminal", v, expected, tolerance).with_note(&format!(
                    "mean radial velocity of the compact band over the last {:.0} % of the run vs the paper's FEM-DEM value; \
                     classic Gurney √(2E0/ρ0)(F/B + ½)^-½ = {:.0} m/s at F/B = {fb:.3}",
                    100.0 * window,
                    gurney_velocity(fem, fb)
                ))
            }
            CheckSpec::BandVelocityBracket { paper } => {
                let v = terminal(cx.history, "band_velocity", window);
                band_velocity_bracket_check(v, cx.models, paper, gurney_velocity(fem, fb), window)
            }
            CheckSpec::RingEnergyTransfer { tolerance } => Check::at_most("ring_energy_transfer_error", transfer_err, tolerance).with_note(
                "|1 − ring kinetic energy / work done by the charge on the ring| at the end (elastic, frictionless grains)",
            ),
            CheckSpec::FillToBurster { expected, tolerance, paper } => fill_to_burster_check(fb, expected, tolerance, paper),
            CheckSpec::ShearBandMode { mode, from, to, at_least, at_most } => {
                shear_band_mode_check(cx.dispersal, mode, (from, to), (at_least, at_most))
            }
            CheckSpec::ShearBandCount { from, to, at_least, at_most } => {
                shear_band_count_check(cx.dispersal, (from, to), (at_least, at_most))
            }
        });
    }
    (checks, fig, arrival)
}

/// The `band_velocity_bracket` check: the terminal band velocity `v` between the
/// compaction estimate (the lower of its φ1 values) and the lossless ceiling, written as
/// an absolute check about the bracket's middle with its half-width as the tolerance.
fn band_velocity_bracket_check(
    v: f64,
    models: Option<&Value>,
    paper: f64,
    gurney: f64,
    window: f64,
) -> Check {
    let ceiling = models.and_then(|m| m["lossless_ceiling"]["velocity"].as_f64());
    let compaction = models
        .and_then(|m| m["compaction"].as_array())
        .map(|c| {
            c.iter()
                .filter_map(|e| e["shell"]["velocity"].as_f64())
                .fold(f64::INFINITY, f64::min)
        })
        .filter(|v| v.is_finite());
    let (lo, hi) = (compaction.unwrap_or(f64::NAN), ceiling.unwrap_or(f64::NAN));
    Check::absolute("band_velocity_bracket", v, 0.5 * (lo + hi), 0.5 * (hi - lo)).with_note(
        &format!(
            "mean radial velocity of the compact band over the last {:.0} % of the run, \
             between the compaction estimate {lo:.0} m/s (φ1 0.88–0.90, the lower) and the \
             lossless JWL-expansion ceiling {hi:.0} m/s at the run's end (figures.models); \
             paper {paper:.0} m/s, classic Gurney {gurney:.0} m/s",
            100.0 * window
        ),
    )
}

/// The mass-ratio check (also run by `grains check`).
pub fn fill_to_burster_check(
    measured: f64,
    expected: f64,
    tolerance: f64,
    paper: Option<f64>,
) -> Check {
    let what = "ring mass (Σ ρπr² of the disks) over charge mass (ρ0 × mesh area)";
    let note = match paper {
        Some(p) => format!("{what}; the paper lists {p}"),
        None => format!("{what}, vs the paper's Table 2"),
    };
    Check::relative("fill_to_burster_ratio", measured, expected, tolerance).with_note(&note)
}

/// The frames of the dispersal analysis at times in [from, to].
fn frames_in(dispersal: Option<&Value>, (from, to): (f64, f64)) -> Vec<&Value> {
    dispersal
        .and_then(|d| d["frames"].as_array())
        .map(|frames| {
            frames
                .iter()
                .filter(|r| r["time"].as_f64().is_some_and(|t| t >= from && t <= to))
                .collect()
        })
        .unwrap_or_default()
}

/// An `at_least` or an `at_most` check, whichever bound is given.
fn bounded(name: &str, measured: f64, (at_least, at_most): (Option<f64>, Option<f64>)) -> Check {
    match (at_least, at_most) {
        (Some(b), _) => Check::at_least(name, measured, b),
        (_, b) => Check::at_most(name, measured, b.unwrap_or(f64::NAN)),
    }
}

/// The `shear_band_count` check: the median number of groups of shear bands over the
/// analysed times in [from, to] that have a band.
fn shear_band_count_check(
    dispersal: Option<&Value>,
    window: (f64, f64),
    bounds: (Option<f64>, Option<f64>),
) -> Check {
    let frames = frames_in(dispersal, window);
    let mut groups: Vec<u64> = frames
        .iter()
        .filter_map(|r| r["shear_bands"]["groups"].as_u64())
        .collect();
    groups.sort_unstable();
    let median = match groups.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => groups[n / 2] as f64,
        n => 0.5 * (groups[n / 2 - 1] + groups[n / 2]) as f64,
    };
    let (lo, hi) = (groups.first().copied(), groups.last().copied());
    bounded("shear_band_groups_median", median, bounds).with_note(&format!(
        "median over the {} of {} times analysed in [{:.1}, {:.1}] µs that have a band \
         (range {}–{}) of the groups of spiral shear bands at the band's inner perimeter, \
         the shear rate's leading azimuthal mode there (xue-2019 §§5.4–5.5, Fig. 11: six \
         groups in an ordered ring, tens in an amorphous one)",
        groups.len(),
        frames.len(),
        window.0 * 1e6,
        window.1 * 1e6,
        lo.map_or("-".into(), |v| v.to_string()),
        hi.map_or("-".into(), |v| v.to_string()),
    ))
}

/// The `shear_band_mode` check: the share of the analysed times in [from, to] at which
/// the shear rate's leading azimuthal mode at the band's inner perimeter is `mode`.
fn shear_band_mode_check(
    dispersal: Option<&Value>,
    mode: usize,
    (from, to): (f64, f64),
    (at_least, at_most): (Option<f64>, Option<f64>),
) -> Check {
    let modes: Vec<Option<u64>> = frames_in(dispersal, (from, to))
        .iter()
        .map(|r| r["shear_bands"]["dominant_mode"].as_u64())
        .collect();
    let hits = modes.iter().filter(|m| **m == Some(mode as u64)).count();
    let share = if modes.is_empty() {
        f64::NAN
    } else {
        hits as f64 / modes.len() as f64
    };
    let name = format!("shear_band_mode_{mode}_share");
    bounded(&name, share, (at_least, at_most)).with_note(&format!(
        "{hits} of the {} times analysed in [{:.1}, {:.1}] µs have the shear rate's leading \
         azimuthal mode (k ≥ 2) at the band's inner perimeter equal to {mode} \
         (xue-2019 §5.5: six groups of spiral shear bands in an ordered ring's hexagonal \
         band, none in an amorphous ring's)",
        modes.len(),
        from * 1e6,
        to * 1e6
    ))
}

#[cfg(test)]
mod tests {
    use super::band_velocity_bracket_check;
    use serde_json::json;

    #[test]
    fn bracket_runs_from_the_lower_compaction_estimate_to_the_ceiling() {
        let models = json!({
            "lossless_ceiling": { "velocity": 700.0 },
            "compaction": [ { "shell": { "velocity": 620.0 } }, { "shell": { "velocity": 600.0 } } ],
        });
        let check = |v| band_velocity_bracket_check(v, Some(&models), 1050.0, 900.0, 0.1);
        let c = check(650.0);
        assert!(c.pass);
        assert_eq!((c.expected, c.tolerance), (650.0, 50.0));
        assert!(check(600.0).pass && check(700.0).pass);
        assert!(!check(599.0).pass && !check(701.0).pass && !check(f64::NAN).pass);
        assert!(!band_velocity_bracket_check(650.0, None, 1050.0, 900.0, 0.1).pass);
    }
}
