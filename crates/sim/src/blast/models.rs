//! The one-dimensional ring models set beside every ring run (`figures.models`):
//! classic Gurney, the lossless JWL-expansion ceiling at the run's end time and the
//! compaction (snowplough) estimate, all for the run's explosive and F/B
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
                "note": "F/B over the explosive filling the charge radius (ρ0πR²); the \
                         lossless ceiling is the JWL isentrope through E0 driving a thin \
                         shell to the run's end time; compaction: the ring swept up by a \
                         front compacting it to φ1, inelastically",
            }),
            Err(e) => json!({ "error": e.to_string() }),
        },
    )
}
