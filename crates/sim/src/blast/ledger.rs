//! Where the charge's work on the ring went (`figures.energy_ledger`, `ring_energy.png`):
//! the grains' kinetic energy (translational and rotational), the energy stored in
//! their contacts, and what contact damping, friction and dropped tangential springs
//! dissipated (the DEM's ledger, `grains_dem::ledger`), against the work the products
//! did through the penalty contact less what its springs hold.

use grains_core::history::History;
use grains_core::plot::{LinePlot, Series};
use serde_json::{json, Value};
use std::path::Path;

/// The ledger at the end of the run, if the history has its columns.
pub fn figures(h: &History) -> Option<Value> {
    let last = |name: &str| h.column(name).and_then(|c| c.last().copied());
    let work = -last("work_on_charge")?;
    let coupling = last("coupling_energy")?;
    let kt = last("particle_kinetic")?;
    let kr = last("particle_rotational")?;
    let stored = last("contact_stored")?;
    let damping = last("contact_damping")?;
    let sliding = last("contact_friction")?;
    let released = last("springs_released")?;
    let friction = sliding + released;
    let into_grains = work - coupling;
    let unaccounted = into_grains - kt - kr - stored - damping - friction;
    let share = |v: f64| if work > 0.0 { v / work } else { f64::NAN };
    Some(json!({
        "work_on_ring": work,
        "coupling_stored": coupling,
        "kinetic_translational": kt,
        "kinetic_rotational": kr,
        "contact_stored": stored,
        "contact_damping": damping,
        "contact_friction": friction,
        "friction_sliding": sliding,
        "friction_springs_released": released,
        "unaccounted": unaccounted,
        "fractions_of_work": {
            "kinetic_translational": share(kt),
            "kinetic_rotational": share(kr),
            "contact_stored": share(stored),
            "contact_damping": share(damping),
            "contact_friction": share(friction),
            "coupling_stored": share(coupling),
            "unaccounted": share(unaccounted),
        },
        "note": "J/m. work_on_ring − coupling_stored = kinetic + contact_stored + \
                 contact_damping + contact_friction + unaccounted; contact_friction is \
                 Coulomb sliding plus the tangential springs dropped when contacts open; \
                 unaccounted is the integrator's error (the ledger reads the slip at the \
                 half step)",
    }))
}

/// The ledger over time (`ring_energy.png`), if the history has its columns.
pub fn plot(dir: &Path, h: &History) -> anyhow::Result<()> {
    let col = |name: &str| h.column(name);
    let (Some(t), Some(w), Some(cp), Some(kt), Some(kr), Some(st), Some(dm), Some(fr), Some(sr)) = (
        col("time"),
        col("work_on_charge"),
        col("coupling_energy"),
        col("particle_kinetic"),
        col("particle_rotational"),
        col("contact_stored"),
        col("contact_damping"),
        col("contact_friction"),
        col("springs_released"),
    ) else {
        return Ok(());
    };
    let t_us: Vec<f64> = t.iter().map(|t| t * 1e6).collect();
    let into: Vec<f64> = w.iter().zip(&cp).map(|(w, c)| -w - c).collect();
    let friction: Vec<f64> = fr.iter().zip(&sr).map(|(a, b)| a + b).collect();
    let series = [
        ("work on the grains (through the penalty contact)", &into),
        ("kinetic, translational", &kt),
        ("kinetic, rotational", &kr),
        ("stored in contacts", &st),
        ("dissipated: contact damping", &dm),
        ("dissipated: friction", &friction),
    ];
    LinePlot {
        title: "Where the products' work on the ring went (energy ledger)",
        x_label: "time (µs)",
        y_label: "energy (J/m)",
        series: series
            .iter()
            .map(|(name, y)| Series { name, x: &t_us, y })
            .collect(),
        log_y: false,
        points: false,
    }
    .write_png_and_csv(&dir.join("ring_energy.png"))?;
    Ok(())
}
