//! The one-dimensional ring models set beside every ring run (`figures.models`):
//! classic Gurney, the lossless JWL-expansion ceiling at the run's end time, the
//! compaction (snowplough) estimate and Milne's porous-shell Gurney velocity (as
//! reconstructed), all for the run's explosive, F/B and packing fraction
//! (`shared/reference/dispersal-models.md`, `grains_fem::shell`).

use super::assemble::explosive;
use super::scenario::Scenario;
use grains_fem::shell::{ring_models, RingGeometry};
use serde_json::{json, Value};

/// Packing fractions the compaction front compacts to: 0.88–0.90 bracket what the DEM
/// rings reach (dispersal-models.md).
pub const COMPACTED: [f64; 2] = [0.88, 0.90];

/// The models for the ring of `s` of mass `ring_mass` (kg/m) at `t_end` (s); None
/// without a ring or with a ring the models cannot describe (its message then says why).
pub fn figures(s: &Scenario, ring_mass: f64, t_end: f64) -> Option<Value> {
    let ring = s.ring.as_ref()?;
    let x = explosive(s).ok()?;
    let density = s
        .materials
        .iter()
        .find(|m| m.name == ring.material)?
        .density;
    let geometry = RingGeometry {
        inner_radius: s.charge.radius,
        outer_radius: ring.outer_radius,
        solid_density: density,
        packing_fraction: 0.5,
    };
    let full =
        density * std::f64::consts::PI * (ring.outer_radius.powi(2) - s.charge.radius.powi(2));
    Some(
        match ring_models(&x, &geometry, ring_mass, t_end, &COMPACTED) {
            Ok(m) => json!({
                "explosive": x.name,
                "time": t_end,
                "fill_to_burster": m.fill_to_burster,
                "packing_fraction": ring_mass / full,
                "classic_gurney": m.classic_gurney,
                "lossless_ceiling": m.lossless,
                "compaction": m.compaction,
                "milne_porous_gurney": m.milne,
                "note": "F/B over the explosive filling the charge radius (ρ0πR²); the \
                         lossless ceiling is the JWL isentrope through E0 driving a thin \
                         shell to the run's end time; compaction: the ring swept up by a \
                         front compacting it to φ1, inelastically; milne_porous_gurney: \
                         xue-2019 Eq. 9 (Milne 2016) as reconstructed, classic Gurney less \
                         half the gas's work while it fills the ring's pores",
            }),
            Err(e) => json!({ "error": e.to_string() }),
        },
    )
}
