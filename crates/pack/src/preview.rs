//! What a spec will make, known before it is made: the disks of the lattice start at
//! the sizes the protocol ends with. `grains check` sizes a ring test from it (disk
//! count, mass, smallest disk) without running the protocol.
//!
//! From the lattice every site keeps its disk, so the count is exact. The sizes are
//! the drawn ones times the final scale: exact when the growth ends at the target
//! fraction; for growth to jamming, [`JAMMED_SCALE`] (measured).

use crate::lattice::{lattice_fill, template};
use crate::lining::lining;
use crate::protocol::{end_scale, scale_region, spread};
use crate::spec::{PackSpec, StartSpec};
use crate::validate::Validated;
use glam::DVec2;
use grains_core::rng;
use rand::RngExt;

/// Final radius scale of a lattice start grown to jamming, relative to the drawn sizes:
/// 0.992 (test-2 ring, 0.31 M disks), 0.995 (R_out = 40 mm, 1.3 M) and 0.991 (test-1
/// ring, 1.9 M) measured; the mass is then within 1 % of the estimate.
pub const JAMMED_SCALE: f64 = 0.992;

/// The disks a spec will make, in SI units: the lining first.
#[derive(Clone, Debug)]
pub struct Preview {
    /// Centres (m).
    pub pos: Vec<DVec2>,
    /// Radii (m).
    pub radius: Vec<f64>,
    /// Leading lining disks.
    pub lining: usize,
}

/// The preview of `spec`; `None` for a deposition start, whose count is only known
/// once the disks have been poured.
pub fn preview(spec: &PackSpec, v: &Validated) -> Option<Preview> {
    if spec.protocol.start != StartSpec::Lattice {
        return None;
    }
    let d0 = v.d0;
    let region = scale_region(&v.region, 1.0 / d0);
    let phase = rng::stream(spec.seed, 1).random::<f64>();
    let lining_disks = lining(&region, spec.lining.diameter_ratio, phase);
    let mut size_rng = rng::stream(spec.seed, 0);
    let t = template(
        &region,
        &lining_disks,
        &v.sizes,
        d0,
        lattice_fill(&spec.protocol),
        spec.seed,
        &mut size_rng,
    );
    let r_lining = t.radius[..t.fixed].iter().copied().fold(0.0, f64::max);
    let s = end_scale(
        &spec.protocol,
        spread(&region, &t.radius[t.fixed..], r_lining),
    )
    .unwrap_or(JAMMED_SCALE);
    Some(Preview {
        pos: t.pos.iter().map(|p| *p * d0).collect(),
        radius: t
            .radius
            .iter()
            .enumerate()
            .map(|(i, r)| if i < t.fixed { r * d0 } else { r * s * d0 })
            .collect(),
        lining: t.fixed,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::{packing_text, verify, Untrusted};

    const SPEC: &str = r#"
name = "p"
seed = 7
[domain]
shape = "annulus"
r_in = 0.002
r_out = 0.004
[sizes]
distribution = "gaussian"
d0 = 0.1e-3
delta = 0.113
[protocol]
rate = 1e-3
finish = "target"
target_fraction = 0.8
"#;

    fn made(text: &str) -> (PackSpec, crate::Packing, Validated) {
        let spec = crate::parse(text, "spec").unwrap();
        let v = crate::validate(&spec).unwrap();
        let p = crate::pack(&spec, &v, &mut |_: String| {});
        (spec, p, v)
    }

    #[test]
    fn the_preview_is_the_packing_to_be() {
        let (spec, p, v) = made(SPEC);
        let pv = preview(&spec, &v).unwrap();
        assert_eq!(pv.pos.len(), p.pos.len());
        assert_eq!(pv.lining, p.lining);
        // Grown to the target: the same sizes, so the same mass to rounding.
        let area = |r: &[f64]| r.iter().map(|r| r * r).sum::<f64>();
        let ratio = area(&pv.radius) / area(&p.radius);
        assert!((ratio - 1.0).abs() < 1e-9, "{ratio}");
        // The bulk disks fill about the target (disks drift toward the walls' gaps).
        assert!(
            (p.stats.fraction_bulk - 0.8).abs() < 0.03,
            "{}",
            p.stats.fraction_bulk
        );
        assert_eq!(p.stats.swell_cycles, 0);
    }

    #[test]
    fn keys_catch_edits_truncation_and_another_spec() {
        let (spec, p, _) = made(SPEC);
        let text = packing_text(&spec, &p, &[]);
        assert_eq!(verify(&text, spec.key()), Ok(()));
        let last = text.trim_end().rsplit('\n').next().unwrap();
        let edited = text.replacen(last, &last.replacen('e', "1e", 1), 1);
        assert!(matches!(
            verify(&edited, spec.key()),
            Err(Untrusted::Content { .. })
        ));
        let cut = &text[..text.len() - 10];
        assert!(matches!(
            verify(cut, spec.key()),
            Err(Untrusted::Content { .. })
        ));
        assert_eq!(
            verify(&text, spec.key() ^ 1),
            Err(Untrusted::Spec { stated: spec.key() })
        );
        let bare: String = text.lines().skip(1).map(|l| format!("{l}\n")).collect();
        assert_eq!(verify(&bare, spec.key()), Err(Untrusted::NoKeys));
    }

    #[test]
    fn the_key_follows_what_shapes_the_packing() {
        let key = |t: &str| crate::parse(t, "spec").unwrap().key();
        let k = key(SPEC);
        assert_eq!(
            k,
            key(&SPEC.replace("name = \"p\"", "name = \"q\"\ndescription = \"x\""))
        );
        assert_eq!(
            k,
            key(&format!(
                "{SPEC}[[check]]\nfigure = \"particles\"\nat_least = 1.0\n"
            ))
        );
        assert_ne!(k, key(&SPEC.replace("seed = 7", "seed = 8")));
        assert_ne!(k, key(&SPEC.replace("rate = 1e-3", "rate = 2e-3")));
        assert_ne!(k, key(&SPEC.replace("r_out = 0.004", "r_out = 0.0041")));
    }
}
