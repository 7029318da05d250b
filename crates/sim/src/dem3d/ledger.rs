//! The grains' energy ledger in a 3D run (`[analysis] energy_ledger`, default on, as the
//! FEM–DEM ring's): history columns, the energies plot with what was dissipated and what
//! the law changed without work (`energy_ledger.png` and its CSV), the ledger's figures
//! in summary.json and the `energy_closure` check. The ledger itself is the engine's
//! (`grains_dem3d::ledger`); it observes only, the run's state is the same bit for bit.
//!
//! Closure: E(t) = kinetic + potential + stored, and E(t) + booked − wall work − poured
//! energy = E(0), up to the integrator's error (first order in Δt; docs/architecture.md,
//! *The energy ledger*). Spheres a pour brings in carry their kinetic and potential
//! energy in from outside: booked as `poured_energy`, work in.

use super::Dem3;
use grains_core::checks::Check;
use grains_core::history::History;
use grains_core::plot::{LinePlot, Series};
use grains_core::snapshot::{get_f64, put_f64, SnapshotError};
use grains_dem3d::diagnostics::Diagnostics;
use grains_dem3d::ledger::LEDGER_WORDS;
use grains_dem3d::{EnergyLedger, LedgerSums, State};
use serde_json::{json, Value};
use std::io::{Read, Write};
use std::path::Path;

/// History columns of the ledger (J).
pub const COLUMNS: [&str; 13] = [
    "contact_stored",
    "dissipated_damping",
    "dissipated_friction",
    "dissipated_springs_released",
    "dissipated_rolling",
    "dissipated_twisting",
    "nonwork_softening",
    "nonwork_lever",
    "wall_work",
    "poured_energy",
    "ledger_balance",
    "ledger_residual",
    "ledger_reference",
];

/// Where the ledger of a run stands: what it started from and what came in by pouring.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Books {
    /// E(0): kinetic + potential + stored when the ledger started (J).
    pub start: f64,
    /// Kinetic + potential energy of the spheres poured in since (J).
    pub poured: f64,
}

/// Kinetic + potential + stored energy of a state with diagnostics `d`.
fn energy(d: &Diagnostics, l: &EnergyLedger) -> f64 {
    d.kinetic() + d.potential + l.stored()
}

/// The energy that went through the ledger: what it booked out (dissipated, and the
/// law's changes without work, in magnitude) and what came in (the walls' work, the
/// poured spheres'): the residual's reference.
fn reference(l: &EnergyLedger, b: &Books) -> f64 {
    l.dissipated() + l.softening.abs() + l.lever.abs() + l.wall_work.abs() + b.poured.abs()
}

/// E(t) + booked − work in − E(0): zero but for the integrator's error.
fn residual(d: &Diagnostics, l: &EnergyLedger, b: &Books) -> f64 {
    energy(d, l) + l.total() - l.wall_work - b.poured - b.start
}

/// The ledger's history row (in [`COLUMNS`] order).
pub fn row(sim: &Dem3, d: &Diagnostics) -> Option<Vec<f64>> {
    let (l, b) = (sim.ledger.as_ref()?, &sim.books);
    let res = residual(d, l, b);
    Some(vec![
        l.stored(),
        l.damping,
        l.friction,
        l.springs_released,
        l.rolling_damping + l.rolling_friction,
        l.twisting_damping + l.twisting_friction,
        l.softening,
        l.lever,
        l.wall_work,
        b.poured,
        res + b.start,
        res,
        reference(l, b),
    ])
}

/// Starts the books of a run whose ledger has just started (on the whole state), with
/// diagnostics `d`.
pub fn open(sim: &mut Dem3, d: &Diagnostics) {
    sim.ledger = grains_dem3d::ledger_sums::figures(&sim.state);
    if let Some(l) = &sim.ledger {
        sim.books = Books {
            start: energy(d, l),
            poured: 0.0,
        };
    }
}

/// The kinetic + potential energy of the spheres `new` a pour just brought in, added in
/// the order of their ids (the same on any rank count).
pub fn brought_in(setup: &grains_dem3d::Setup, new: &grains_dem3d::Particles) -> f64 {
    (0..new.len())
        .map(|i| {
            let m = new.mass(i);
            0.5 * m * new.vel[i].length_squared()
                + 0.5 * new.omega[i].length_squared() / new.inv_inertia[i]
                - m * setup.gravity.dot(new.pos[i])
        })
        .sum()
}

/// Appends the ledger to a checkpoint's bytes (nothing without a ledger): the exact
/// sums of what left the run (their words' bits as numbers) and the books, then every
/// sphere's running ledger in ascending id. A resumed run's ledger goes on as the
/// straight run's, bit for bit.
pub fn write_tail(sim: &Dem3, w: &mut impl Write) -> std::io::Result<()> {
    let Some(departed) = &sim.state.ledger else {
        return put_f64(w, &[]);
    };
    let words: Vec<f64> = departed
        .to_words()
        .into_iter()
        .map(f64::from_bits)
        .chain([sim.books.start, sim.books.poured])
        .collect();
    put_f64(w, &words)?;
    put_f64(w, &grains_dem3d::ledger_sums::rows_by_id(&sim.state))
}

/// Reads what [`write_tail`] appended: the ledger into `state`, and its books (none
/// from a checkpoint written without it). A checkpoint of the ledger's figures alone
/// (written before the spheres kept their own) is refused: its ledger cannot go on.
pub fn read_tail(r: &mut impl Read, state: &mut State) -> Result<Books, SnapshotError> {
    let mut peek = [0u8; 1];
    if r.read(&mut peek)? == 0 {
        return Ok(Books::default());
    }
    let mut r = (&peek[..]).chain(r);
    let words = get_f64(&mut r, LedgerSums::WORDS + 2)?;
    if words.is_empty() {
        return Ok(Books::default());
    }
    let (sums, books) = words.split_at(words.len().saturating_sub(2));
    let bits: Vec<u64> = sums.iter().map(|x| x.to_bits()).collect();
    let (Some(departed), &[start, poured]) = (LedgerSums::from_words(&bits), books) else {
        return Err(SnapshotError::Invalid(format!(
            "the energy ledger has {} numbers, not {}{}",
            words.len(),
            LedgerSums::WORDS + 2,
            if words.len() == LEDGER_WORDS + 2 {
                " (written by an older build, before each sphere kept its own ledger: \
                 it cannot go on; start the run again)"
            } else {
                ""
            }
        )));
    };
    let n = state.particles.len();
    let rows = get_f64(&mut r, LEDGER_WORDS * n)?;
    grains_dem3d::ledger_sums::read_rows(state, &rows).map_err(SnapshotError::Invalid)?;
    state.ledger = Some(departed);
    Ok(Books { start, poured })
}

/// The `energy_closure` check: |residual| / reference at the end, at most `limit`.
pub fn check(name: &str, sim: &Dem3, d: &Diagnostics, limit: f64) -> Check {
    match &sim.ledger {
        Some(l) => {
            let r = residual(d, l, &sim.books).abs() / reference(l, &sim.books);
            Check::at_most(name, r, limit)
        }
        None => Check::at_most(name, f64::NAN, limit)
            .with_note("the energy ledger is off ([analysis] energy_ledger = false)"),
    }
}

/// The ledger at the end (`figures.energy_ledger`), if the history has its columns.
pub fn figures(h: &History) -> Option<Value> {
    let last = |name: &str| h.column(name).and_then(|c| c.last().copied());
    let first = |name: &str| h.column(name).and_then(|c| c.first().copied());
    let mut out = serde_json::Map::new();
    for c in COLUMNS {
        out.insert(c.into(), last(c)?.into());
    }
    out.insert("kinetic".into(), last("kinetic")?.into());
    out.insert(
        "potential_change".into(),
        (last("potential")? - first("potential")?).into(),
    );
    out.insert("initial".into(), (first("ledger_balance")?).into());
    let (res, reference) = (last("ledger_residual")?, last("ledger_reference")?);
    out.insert("closure".into(), (res.abs() / reference).into());
    out.insert(
        "note".into(),
        json!(
            "J. kinetic + potential + contact_stored + dissipated_* + nonwork_* − wall_work \
             − poured_energy = initial + ledger_residual (ledger_balance is the left side); \
             closure = |ledger_residual| / ledger_reference, the reference being the \
             energy booked through the ledger (dissipated, |non-work|, |wall work|, \
             |poured|); the residual is the integrator's error, first order in dt"
        ),
    );
    Some(Value::Object(out))
}

/// The energies over time with the ledger (`energy_ledger.png` and its CSV), if the
/// history has its columns.
pub fn plot(dir: &Path, h: &History) -> anyhow::Result<()> {
    let col = |name: &str| h.column(name);
    let (Some(t), Some(k), Some(pot), Some(bal)) = (
        col("time"),
        col("kinetic"),
        col("potential"),
        col("ledger_balance"),
    ) else {
        return Ok(());
    };
    let Some(cols) = COLUMNS[..10]
        .iter()
        .map(|c| col(c))
        .collect::<Option<Vec<Vec<f64>>>>()
    else {
        return Ok(());
    };
    let (p0, e0) = (pot[0], bal[0]);
    let potential: Vec<f64> = pot.iter().map(|p| p - p0).collect();
    let total: Vec<f64> = bal.iter().map(|b| b - e0).collect();
    let nonwork: Vec<f64> = cols[6].iter().zip(&cols[7]).map(|(a, b)| a + b).collect();
    let work_in: Vec<f64> = cols[8].iter().zip(&cols[9]).map(|(a, b)| a + b).collect();
    let series: Vec<(&str, &[f64])> = vec![
        ("kinetic", &k),
        ("potential − initial", &potential),
        ("stored in contacts", &cols[0]),
        ("dissipated: damping", &cols[1]),
        ("dissipated: friction", &cols[2]),
        ("dissipated: springs released", &cols[3]),
        ("dissipated: rolling", &cols[4]),
        ("dissipated: twisting", &cols[5]),
        ("non-work: softening + lever", &nonwork),
        ("work in: walls + poured", &work_in),
        ("total − initial (all above − work in)", &total),
    ];
    LinePlot {
        title: "Energy ledger: where the energy went",
        x_label: "time (s)",
        y_label: "energy (J)",
        series: series
            .iter()
            .map(|(name, y)| Series { name, x: &t, y })
            .collect(),
        log_y: false,
        points: false,
    }
    .write_png_and_csv(&dir.join("energy_ledger.png"))?;
    Ok(())
}
