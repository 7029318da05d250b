//! What each `[[check]]` needs of the scenario, verified before anything runs: the
//! bodies it names exist, its bounds are positive, and the set-up is one the check's
//! reference solution applies to (a perfectly plastic J2 body for the shear plateau, a
//! one-term Maxwell body for the relaxation time, a heated body for the thermal checks,
//! a disk and the ring around it for the concentric cylinders).

use super::concentric::Concentric;
use super::scenario::{CheckSpec, Region, Scenario, ShearSpec};
use glam::DVec2;
use grains_core::input::{positive, InputError};
use grains_mpm::{Geometry, Material, Motion, Setup};

/// Checks every `[[check]]` of `s` against the assembled `setup` and body `shapes`.
pub fn validate(
    s: &Scenario,
    setup: &Setup,
    shapes: &[Geometry],
    names: &[&str],
) -> Result<(), InputError> {
    if let Some(cell) = &s.shear {
        shear(cell, setup, names)?;
    } else if let Some((k, c)) = s
        .checks
        .iter()
        .enumerate()
        .find(|(_, c)| matches!(c, CheckSpec::ShearStrainReached { .. }))
    {
        return Err(InputError::new(
            format!("check[{k}].kind"),
            format!("\"{}\"", c.name()),
            "a shear_strain_reached check needs a [shear] cell",
        ));
    }
    for (k, c) in s.checks.iter().enumerate() {
        let key = format!("check[{k}]");
        for (field, b) in c.bodies() {
            if !names.contains(&b) {
                return Err(InputError::new(
                    format!("{key}.{field}"),
                    format!("\"{b}\""),
                    format!("must be one of {names:?}"),
                ));
            }
        }
        let index = |b: &str| names.iter().position(|n| *n == b).expect("checked above");
        for (field, v) in bounds(c) {
            positive(&format!("{key}.{field}"), v)?;
        }
        let refuse = |field: &str, value: String, why: String| {
            Err(InputError::new(format!("{key}.{field}"), value, why))
        };
        let material = |b: &str| &setup.materials[setup.bodies[index(b)].material];
        match c {
            CheckSpec::InitialEnergy { .. } | CheckSpec::InitialMomentum { .. }
                if s.bodies.iter().any(|b| b.velocity_gradient.is_some()) =>
            {
                return refuse(
                    "kind",
                    format!("\"{}\"", c.name()),
                    "compares with uniform initial velocities; a body has a velocity_gradient"
                        .into(),
                );
            }
            CheckSpec::InitialMomentum { component, .. }
                if component != "x" && component != "y" =>
            {
                return refuse(
                    "component",
                    format!("\"{component}\""),
                    "must be \"x\" or \"y\"".into(),
                );
            }
            CheckSpec::EnergyLoss {
                after_impact: 0, ..
            }
            | CheckSpec::EnergyLossBelowReference {
                after_impact: 0, ..
            } => return refuse("after_impact", "0".into(), "impacts count from 1".into()),
            CheckSpec::ImpactTangentialVelocity { impact: 0, .. }
            | CheckSpec::ImpactSpin { impact: 0, .. } => {
                return refuse("impact", "0".into(), "impacts count from 1".into())
            }
            CheckSpec::Acceleration { normal, .. } => {
                let n = DVec2::from(*normal);
                if !(n.is_finite() && n.length() > 0.0) {
                    return refuse(
                        "normal",
                        format!("{normal:?}"),
                        "must be a finite non-zero vector".into(),
                    );
                }
                if s.gravity == [0.0, 0.0] {
                    return Err(InputError::new(
                        "gravity",
                        "[0, 0]",
                        format!("{key} needs gravity"),
                    ));
                }
            }
            CheckSpec::ShearStressPlateau { body, region, .. }
            | CheckSpec::HardeningSlope { body, region, .. }
            | CheckSpec::RelaxationTime { body, region, .. } => {
                region_ok(&key, region)?;
                let plateau = matches!(c, CheckSpec::ShearStressPlateau { .. });
                let fits = match (c, material(body)) {
                    (CheckSpec::RelaxationTime { .. }, Material::Maxwell { shear, prony, .. }) => {
                        *shear == 0.0 && prony.len() == 1
                    }
                    (CheckSpec::RelaxationTime { .. }, _) => false,
                    (_, Material::J2Plastic { hardening, .. }) => (*hardening == 0.0) == plateau,
                    _ => false,
                };
                if !fits {
                    let needs = match c {
                        CheckSpec::ShearStressPlateau { .. } => {
                            "a J2 body with hardening = 0 (perfectly plastic)"
                        }
                        CheckSpec::HardeningSlope { .. } => "a J2 body with hardening > 0",
                        _ => "a Maxwell body with one Prony term and shear (G∞) = 0",
                    };
                    return refuse("body", format!("\"{body}\""), format!("needs {needs}"));
                }
                if let CheckSpec::RelaxationTime { after, .. } = c {
                    if !(after.is_finite() && *after >= 0.0 && *after < s.run.duration) {
                        return refuse(
                            "after",
                            after.to_string(),
                            format!("must be in [0, run.duration = {})", s.run.duration),
                        );
                    }
                }
            }
            CheckSpec::ThermalStrain { body, .. }
            | CheckSpec::InPlaneStress { body, .. }
            | CheckSpec::OutOfPlaneStress { body, .. } => {
                let b = &setup.bodies[index(body)];
                let change = b
                    .temperature
                    .as_ref()
                    .map_or(0.0, |h| h.at(s.run.duration) - h.at(0.0));
                if b.motion != Motion::Free || material(body).expansion() == 0.0 || change == 0.0 {
                    return refuse(
                        "body",
                        format!("\"{body}\""),
                        "needs a free body with expansion > 0 whose temperature changes over the run".into(),
                    );
                }
            }
            CheckSpec::InterfaceRadialStress { inner, outer, .. }
            | CheckSpec::DebondOnsetTime { inner, outer, .. }
            | CheckSpec::DebondSpeedOverRayleigh { inner, outer, .. } => {
                let pair = match Concentric::new(shapes, index(inner), index(outer)) {
                    Ok(p) => p,
                    Err(e) => return refuse("inner", format!("\"{inner}\""), e),
                };
                if let CheckSpec::InterfaceRadialStress { core, after, .. } = c {
                    if !(*core > 0.0 && *core <= 1.0) {
                        return refuse("core", core.to_string(), "must be in (0, 1]".into());
                    }
                    if !(after.is_finite() && *after >= 0.0 && *after < s.run.duration) {
                        return refuse(
                            "after",
                            after.to_string(),
                            format!("must be in [0, run.duration = {})", s.run.duration),
                        );
                    }
                } else if pair.bond(setup).is_none() {
                    return refuse(
                        "outer",
                        format!("\"{outer}\""),
                        format!(
                            "must be bonded to \"{inner}\" ([[contact.pair]] law = \"bonded\")"
                        ),
                    );
                }
                if let CheckSpec::DebondSpeedOverRayleigh { range, .. } = c {
                    if !(range[0].is_finite() && range[1].is_finite() && range[0] < range[1]) {
                        return refuse(
                            "range",
                            format!("{range:?}"),
                            "must be [lo, hi] with lo < hi".into(),
                        );
                    }
                }
            }
            CheckSpec::StressFreeAfterDebond { body, after, .. } => {
                if setup.contact.bond_of(index(body)) <= 0.0 {
                    return refuse(
                        "body",
                        format!("\"{body}\""),
                        "must be bonded to another body".into(),
                    );
                }
                if !(after.is_finite() && *after >= 0.0) {
                    return refuse(
                        "after",
                        after.to_string(),
                        "must be a finite number >= 0".into(),
                    );
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// A `[shear]` cell: its boundaries are rigid bodies, its binder a free one.
fn shear(cell: &ShearSpec, setup: &Setup, names: &[&str]) -> Result<(), InputError> {
    let find = |key: String, name: &str| {
        names.iter().position(|n| *n == name).ok_or_else(|| {
            InputError::new(
                key,
                format!("\"{name}\""),
                format!("must be one of {names:?}"),
            )
        })
    };
    for (side, list) in [("left", &cell.left), ("right", &cell.right)] {
        if list.is_empty() {
            return Err(InputError::new(
                format!("shear.{side}"),
                "[]",
                "name the rigid bodies of the boundary",
            ));
        }
        for (k, name) in list.iter().enumerate() {
            let b = find(format!("shear.{side}[{k}]"), name)?;
            if setup.bodies[b].motion == Motion::Free {
                return Err(InputError::new(
                    format!("shear.{side}[{k}]"),
                    format!("\"{name}\""),
                    "must be a rigid body (rigid = true): a boundary moves as prescribed",
                ));
            }
        }
    }
    if let Some(name) = &cell.binder {
        let b = find("shear.binder".into(), name)?;
        if setup.bodies[b].motion != Motion::Free || setup.contact.bond_of(b) <= 0.0 {
            return Err(InputError::new(
                "shear.binder",
                format!("\"{name}\""),
                "must be a free body bonded to the grains",
            ));
        }
    }
    positive("shear.lock_threshold", cell.lock_threshold)
}

/// The check's bounds that must be finite and positive, by key.
fn bounds(c: &CheckSpec) -> Vec<(&'static str, f64)> {
    match c {
        CheckSpec::InitialEnergy { tolerance, .. }
        | CheckSpec::InitialMomentum { tolerance, .. }
        | CheckSpec::ImpactTangentialVelocity { tolerance, .. }
        | CheckSpec::ImpactSpin { tolerance, .. }
        | CheckSpec::Acceleration { tolerance, .. }
        | CheckSpec::ShearStressPlateau { tolerance, .. }
        | CheckSpec::HardeningSlope { tolerance, .. }
        | CheckSpec::RelaxationTime { tolerance, .. }
        | CheckSpec::ThermalStrain { tolerance, .. }
        | CheckSpec::OutOfPlaneStress { tolerance, .. }
        | CheckSpec::InterfaceRadialStress { tolerance, .. }
        | CheckSpec::DebondOnsetTime { tolerance, .. } => vec![("tolerance", *tolerance)],
        CheckSpec::EnergyLoss { max, .. }
        | CheckSpec::TangentialMomentumChange { max, .. }
        | CheckSpec::InPlaneStress { max, .. }
        | CheckSpec::EnergyBalance { max, .. }
        | CheckSpec::EnergyLedger { max, .. }
        | CheckSpec::ContactMomentumImbalance { max, .. }
        | CheckSpec::StressFreeAfterDebond { max, .. } => vec![("max", *max)],
        CheckSpec::ShearStrainReached { min, .. } => vec![("min", *min)],
        CheckSpec::Rotation { max_deg, .. } => vec![("max_deg", *max_deg)],
        CheckSpec::EnergyLossBelowReference { .. } | CheckSpec::DebondSpeedOverRayleigh { .. } => {
            vec![]
        }
    }
}

fn region_ok(key: &str, r: &Region) -> Result<(), InputError> {
    let finite = r.lo.iter().chain(&r.hi).all(|x| x.is_finite());
    if finite && r.hi[0] > r.lo[0] && r.hi[1] > r.lo[1] {
        Ok(())
    } else {
        Err(InputError::new(
            format!("{key}.region"),
            format!("{{ lo = {:?}, hi = {:?} }}", r.lo, r.hi),
            "hi must lie above lo in x and y, all finite",
        ))
    }
}
