//! The contact law of each material pair from the scenario's `[contact]` table (LAMMPS's
//! keywords), validated: either one linear law for every pair (the engine's kernel: the
//! material route in 2D, or `hooke_history`), or a table of granular laws in which a
//! `hooke_history` pair becomes LAMMPS `granular hooke … mass_velocity … linear_history`.

use super::engine::granular::{
    effective_shear, effective_youngs, tsuji_alpha, Damping, GranularParams, Normal, Rolling,
    Tangential,
};
use super::engine::math::DIM;
use super::engine::{ContactModel, Material, PairTable};
use super::spec::{LawModel, LawSpec, NormalSpec};
use grains_core::input::{positive, InputError};

/// The laws of a scenario.
pub struct Laws {
    /// The linear model (the engine's kernel when `granular` is `None`).
    pub model: ContactModel,
    /// The granular law of every pair, when any pair has one.
    pub granular: Option<PairTable<GranularParams>>,
    /// The restitution each pair's law is built for, where it takes one.
    pub restitution: PairTable<Option<f64>>,
}

fn nonneg(key: &str, v: f64) -> Result<f64, InputError> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(InputError::new(key, v, "must be a finite number >= 0"))
    }
}

fn given(key: &str, v: Option<f64>, why: &str) -> Result<f64, InputError> {
    v.ok_or_else(|| InputError::new(key, "(missing)", format!("required {why}")))
}

fn absent<T>(key: &str, v: &Option<T>, why: &str) -> Result<(), InputError> {
    match v {
        Some(_) => Err(InputError::new(key, "(given)", format!("not a key {why}"))),
        None => Ok(()),
    }
}

/// The law of the pair of materials `a`, `b`, and the key it is written under.
fn law_of<'a>(c: &'a LawSpec, a: &str, b: &str) -> (&'a LawSpec, String) {
    for (k, p) in c.pair.iter().enumerate() {
        if let Some([x, y]) = &p.materials {
            if (x == a && y == b) || (x == b && y == a) {
                return (p, format!("contact.pair[{k}]"));
            }
        }
    }
    (c, "contact".into())
}

/// The model of the table `l` (written under `key`), one this dimension offers.
fn model_of(l: &LawSpec, key: &str) -> Result<LawModel, InputError> {
    let allowed = if DIM == 2 {
        "one of \"material\", \"hooke_history\", \"granular\""
    } else {
        "one of \"hooke_history\", \"granular\" (\"material\" is 2D's)"
    };
    match l.model {
        None => Err(InputError::new(
            format!("{key}.model"),
            "(missing)",
            allowed,
        )),
        Some(LawModel::Material) if DIM != 2 => Err(InputError::new(
            format!("{key}.model"),
            "\"material\"",
            allowed,
        )),
        Some(m) => Ok(m),
    }
}

/// Checks the table's shape: a model everywhere, `materials` only on pairs (naming
/// materials, each pair once), no pairs within pairs.
fn validate_shape(c: &LawSpec, materials: &[Material]) -> Result<(), InputError> {
    model_of(c, "contact")?;
    absent(
        "contact.materials",
        &c.materials,
        "of [contact] (only of [[contact.pair]])",
    )?;
    let names: Vec<&str> = materials.iter().map(|m| m.name.as_str()).collect();
    for (k, p) in c.pair.iter().enumerate() {
        let key = format!("contact.pair[{k}]");
        let Some(pair) = &p.materials else {
            return Err(InputError::new(
                format!("{key}.materials"),
                "(missing)",
                "the two material names this law is for",
            ));
        };
        for m in pair {
            if !names.contains(&m.as_str()) {
                return Err(InputError::new(
                    format!("{key}.materials"),
                    format!("\"{m}\""),
                    format!("must be one of {names:?}"),
                ));
            }
        }
        if model_of(p, &key)? == LawModel::Material {
            return Err(InputError::new(
                format!("{key}.model"),
                "\"material\"",
                "one of \"hooke_history\", \"granular\" (the material route is one law for every pair)",
            ));
        }
        if !p.pair.is_empty() {
            return Err(InputError::new(
                format!("{key}.pair"),
                "(given)",
                "pairs hold no pairs",
            ));
        }
        if !std::ptr::eq(law_of(c, &pair[0], &pair[1]).0, p) {
            return Err(InputError::new(
                format!("{key}.materials"),
                format!("{pair:?}"),
                "each pair of materials at most once",
            ));
        }
    }
    Ok(())
}

/// The linear law's numbers of `l` (its keys checked).
fn hooke_history(l: &LawSpec, key: &str) -> Result<[f64; 5], InputError> {
    let why = "by model \"hooke_history\"";
    let not = "of model \"hooke_history\"";
    absent(&format!("{key}.normal"), &l.normal, not)?;
    absent(&format!("{key}.damping"), &l.damping, not)?;
    absent(&format!("{key}.tangential"), &l.tangential, not)?;
    absent(&format!("{key}.rolling"), &l.rolling, not)?;
    absent(&format!("{key}.twisting"), &l.twisting, not)?;
    let k = |f: &str| format!("{key}.{f}");
    let kn = given(&k("kn"), l.kn, why)?;
    positive(&k("kn"), kn)?;
    let kt = given(&k("kt"), l.kt, why)?;
    positive(&k("kt"), kt)?;
    let gn = nonneg(&k("gamma_n"), given(&k("gamma_n"), l.gamma_n, why)?)?;
    let gt = nonneg(&k("gamma_t"), given(&k("gamma_t"), l.gamma_t, why)?)?;
    let mu = nonneg(&k("mu"), given(&k("mu"), l.mu, why)?)?;
    Ok([kn, kt, gn, gt, mu])
}

/// The granular law of `l` for materials `a`, `b`, and the restitution it is built for.
fn granular(
    l: &LawSpec,
    key: &str,
    a: &Material,
    b: &Material,
) -> Result<(GranularParams, Option<f64>), InputError> {
    let k = |f: &str| format!("{key}.{f}");
    if l.model == Some(LawModel::HookeHistory) {
        let [kn, kt, gn, gt, mu] = hooke_history(l, key)?;
        if gn == 0.0 && gt > 0.0 {
            return Err(InputError::new(
                k("gamma_t"),
                gt,
                "must be 0 when gamma_n is 0 beside a granular law (its tangential damping is a fraction of the normal one)",
            ));
        }
        let p = GranularParams {
            normal: Normal::Hooke,
            kn,
            damping: Damping::MassVelocity,
            damp: gn,
            tangential: Tangential::LinearHistory,
            kt,
            x_gamma_t: if gn > 0.0 { gt / gn } else { 0.0 },
            mu,
            rolling: None,
            twisting: false,
            limit_damping: l.limit_damping,
        };
        return Ok((p, None));
    }
    let why = "by model \"granular\"";
    absent(
        &k("gamma_n"),
        &l.gamma_n,
        "of model \"granular\" (see damping, damp)",
    )?;
    absent(
        &k("gamma_t"),
        &l.gamma_t,
        "of model \"granular\" (see x_gamma_t)",
    )?;
    let normal = l.normal.ok_or_else(|| {
        InputError::new(
            k("normal"),
            "(missing)",
            format!("required {why}: \"hertz/material\" or \"hooke\""),
        )
    })?;
    let damping = l.damping.ok_or_else(|| {
        InputError::new(
            k("damping"),
            "(missing)",
            format!("required {why}: \"tsuji\", \"restitution\", \"viscoelastic\", \"velocity\" or \"mass_velocity\""),
        )
    })?;
    let tangential = l.tangential.ok_or_else(|| {
        InputError::new(
            k("tangential"),
            "(missing)",
            format!("required {why}: \"mindlin\", \"mindlin_rescale\" or \"linear_history\""),
        )
    })?;
    let material = |m: &Material, f: &str, v: Option<f64>| {
        v.ok_or_else(|| {
            InputError::new(
                format!("material.{}.{f}", m.name),
                "(missing)",
                format!("required by {key}'s law"),
            )
        })
    };
    let elastic = |m: &Material| -> Result<(f64, f64), InputError> {
        Ok((
            material(m, "youngs", m.youngs)?,
            material(m, "poisson", m.poisson)?,
        ))
    };
    let (kn, normal) = match normal {
        NormalSpec::HertzMaterial => {
            absent(
                &k("kn"),
                &l.kn,
                "of normal \"hertz/material\" (E and ν are the materials')",
            )?;
            let ((ea, na), (eb, nb)) = (elastic(a)?, elastic(b)?);
            (
                4.0 / 3.0 * effective_youngs([ea, eb], [na, nb]),
                Normal::HertzMaterial,
            )
        }
        NormalSpec::Hooke => {
            let kn = given(&k("kn"), l.kn, "by normal \"hooke\"")?;
            positive(&k("kn"), kn)?;
            (kn, Normal::Hooke)
        }
    };
    let by_e = matches!(damping, Damping::Tsuji | Damping::Restitution);
    let (damp, e) = if by_e {
        absent(
            &k("damp"),
            &l.damp,
            "of damping \"tsuji\" or \"restitution\" (they take restitution)",
        )?;
        let e = match l.restitution {
            Some(e) => e,
            None => (material(a, "restitution", a.restitution)?
                * material(b, "restitution", b.restitution)?)
            .sqrt(),
        };
        if !(e.is_finite() && e > 0.0 && e <= 1.0) {
            return Err(InputError::new(k("restitution"), e, "must be in (0, 1]"));
        }
        let alpha = if damping == Damping::Tsuji {
            tsuji_alpha(e)
        } else {
            super::engine::restitution::alpha(normal, e)
        };
        (alpha, Some(e))
    } else {
        absent(
            &k("restitution"),
            &l.restitution,
            "of this damping (see damp)",
        )?;
        let d = given(&k("damp"), l.damp, "by this damping (η₀)")?;
        (nonneg(&k("damp"), d)?, None)
    };
    let kt = match (tangential, l.kt) {
        (_, Some(kt)) => {
            positive(&k("kt"), kt)?;
            kt
        }
        (Tangential::LinearHistory, None) => {
            given(&k("kt"), None, "by tangential \"linear_history\"")?
        }
        (_, None) => {
            let ((ea, na), (eb, nb)) = (elastic(a)?, elastic(b)?);
            8.0 * effective_shear([ea, eb], [na, nb])
        }
    };
    let mu = match l.mu {
        Some(mu) => nonneg(&k("mu"), mu)?,
        None => (nonneg(
            &format!("material.{}.friction", a.name),
            material(a, "friction", a.friction)?,
        )? * nonneg(
            &format!("material.{}.friction", b.name),
            material(b, "friction", b.friction)?,
        )?)
        .sqrt(),
    };
    let rolling = match l.rolling.as_deref() {
        None => {
            for (f, v) in [("kr", l.kr), ("gamma_r", l.gamma_r), ("mu_r", l.mu_r)] {
                absent(&k(f), &v, "without rolling = \"sds\"")?;
            }
            None
        }
        Some("sds") => {
            let kr = given(&k("kr"), l.kr, "by rolling \"sds\"")?;
            positive(&k("kr"), kr)?;
            Some(Rolling {
                kr,
                gamma_r: nonneg(
                    &k("gamma_r"),
                    given(&k("gamma_r"), l.gamma_r, "by rolling \"sds\"")?,
                )?,
                mu_r: nonneg(&k("mu_r"), given(&k("mu_r"), l.mu_r, "by rolling \"sds\"")?)?,
            })
        }
        Some(other) => {
            return Err(InputError::new(
                k("rolling"),
                format!("\"{other}\""),
                "must be \"sds\"",
            ));
        }
    };
    let twisting = match l.twisting.as_deref() {
        None => false,
        Some("marshall") if DIM == 2 => {
            return Err(InputError::new(
                k("twisting"),
                "\"marshall\"",
                "not in 2D: a disk turns only about z, so it has no twist (3D scenarios only)",
            ));
        }
        Some("marshall") => true,
        Some(other) => {
            return Err(InputError::new(
                k("twisting"),
                format!("\"{other}\""),
                "must be \"marshall\"",
            ));
        }
    };
    let x_gamma_t = nonneg(&k("x_gamma_t"), l.x_gamma_t.unwrap_or(1.0))?;
    let p = GranularParams {
        normal,
        kn,
        damping,
        damp,
        tangential,
        kt,
        x_gamma_t,
        mu,
        rolling,
        twisting,
        limit_damping: l.limit_damping,
    };
    Ok((p, e))
}

/// The material route (2D): its one key `limit_damping`; the engine's set-up checks
/// that the materials give what it derives the law from.
fn material_route(c: &LawSpec, n: usize) -> Result<Laws, InputError> {
    let not = "of model \"material\" (the law comes from the materials)";
    let k = |f: &str| format!("contact.{f}");
    for (f, v) in [
        ("kn", c.kn),
        ("kt", c.kt),
        ("gamma_n", c.gamma_n),
        ("gamma_t", c.gamma_t),
        ("mu", c.mu),
        ("damp", c.damp),
        ("restitution", c.restitution),
        ("x_gamma_t", c.x_gamma_t),
        ("kr", c.kr),
        ("gamma_r", c.gamma_r),
        ("mu_r", c.mu_r),
    ] {
        absent(&k(f), &v, not)?;
    }
    absent(&k("normal"), &c.normal, not)?;
    absent(&k("damping"), &c.damping, not)?;
    absent(&k("tangential"), &c.tangential, not)?;
    absent(&k("rolling"), &c.rolling, not)?;
    absent(&k("twisting"), &c.twisting, not)?;
    absent(&k("materials"), &c.materials, not)?;
    if !c.pair.is_empty() {
        return Err(InputError::new(
            "contact.pair",
            "(given)",
            "not beside model \"material\" (one law for every pair); give model \"granular\" or \"hooke_history\" to set pairs",
        ));
    }
    Ok(Laws {
        model: ContactModel::Material {
            limit_damping: c.limit_damping,
        },
        granular: None,
        restitution: PairTable::from_fn(n, |_, _| None),
    })
}

/// Resolves every pair's law.
pub fn resolve(c: &LawSpec, materials: &[Material]) -> Result<Laws, InputError> {
    if c.model == Some(LawModel::Material) && DIM == 2 {
        return material_route(c, materials.len());
    }
    // The materials' own ranges first, so that an error names the material's key.
    super::engine::setup::validate_materials(&ContactModel::unused(), materials)?;
    validate_shape(c, materials)?;
    let n = materials.len();
    if c.pair.is_empty() && c.model == Some(LawModel::HookeHistory) {
        let [kn, kt, gamma_n, gamma_t, mu] = hooke_history(c, "contact")?;
        // The linear kernel; the restitution of a pair depends on its masses.
        return Ok(Laws {
            model: ContactModel::HookeHistory {
                kn,
                kt,
                gamma_n,
                gamma_t,
                mu,
                limit_damping: c.limit_damping,
            },
            granular: None,
            restitution: PairTable::from_fn(n, |_, _| None),
        });
    }
    let mut laws = Vec::with_capacity(n * n);
    for a in materials {
        for b in materials {
            let (l, key) = law_of(c, &a.name, &b.name);
            laws.push(granular(l, &key, a, b)?);
        }
    }
    Ok(Laws {
        model: ContactModel::unused(),
        granular: Some(PairTable::from_fn(n, |a, b| laws[a * n + b].0)),
        restitution: PairTable::from_fn(n, |a, b| laws[a * n + b].1),
    })
}
