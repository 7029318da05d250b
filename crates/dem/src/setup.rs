//! The read-only description of a DEM run that every stage reads: domain, walls,
//! contact table, gravity, time step and neighbour skin.

use crate::contact::{ContactModel, PairTable};
use crate::domain::Domain;
use crate::material::Material;
use crate::walls::Wall;
use glam::DVec2;

/// Everything the stages read and never write.
#[derive(Clone, Debug)]
pub struct Setup {
    /// Simulation box and periodicity.
    pub domain: Domain,
    /// Materials, indexed by `Particles::material`.
    pub materials: Vec<Material>,
    /// Contact model the table was built from.
    pub model: ContactModel,
    /// Pair parameters per material pair.
    pub pairs: PairTable,
    /// Rigid walls (at most [`MAX_WALLS`]).
    pub walls: Vec<Wall>,
    /// Gravitational acceleration (m/s²).
    pub gravity: DVec2,
    /// Time step (s).
    pub dt: f64,
    /// Verlet skin (m): pairs closer than r_i + r_j + skin are listed, and the list is
    /// rebuilt once any particle has moved more than skin/2.
    pub skin: f64,
}

/// Walls are tracked per particle in a 64-bit mask of nearby walls.
pub const MAX_WALLS: usize = 64;

/// A rejected input value: names the key, the value and what is allowed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{key} = {value}: {allowed}")]
pub struct SetupError {
    /// Dotted key path in the scenario.
    pub key: String,
    /// The offending value, as text.
    pub value: String,
    /// What would be accepted.
    pub allowed: String,
}

impl SetupError {
    /// Builds an error from its three parts.
    pub fn new(key: impl Into<String>, value: impl Shown, allowed: impl Into<String>) -> Self {
        SetupError {
            key: key.into(),
            value: value.shown(),
            allowed: allowed.into(),
        }
    }
}

/// How a value appears in an error message: numbers far from 1 in scientific notation
/// (`1e-6`, not `0.000001`), so the user recognises what they wrote.
pub trait Shown {
    /// The value as text.
    fn shown(&self) -> String;
}

impl Shown for f64 {
    fn shown(&self) -> String {
        let a = self.abs();
        if a == 0.0 || (1e-3..1e6).contains(&a) || !a.is_finite() {
            format!("{self}")
        } else {
            format!("{self:e}")
        }
    }
}

impl Shown for &f64 {
    fn shown(&self) -> String {
        (**self).shown()
    }
}

macro_rules! shown_by_display {
    ($($t:ty),*) => {$(
        impl Shown for $t {
            fn shown(&self) -> String {
                self.to_string()
            }
        }
    )*};
}
shown_by_display!(&str, String, &String, usize, &usize, u64, u32, i64);

fn positive(key: String, v: f64) -> Result<(), SetupError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(SetupError::new(key, v, "must be a finite number > 0"))
    }
}

/// Checks that every material carries what the contact model needs, in range.
pub fn validate_materials(model: &ContactModel, materials: &[Material]) -> Result<(), SetupError> {
    for m in materials {
        let key = |f: &str| format!("material.{}.{}", m.name, f);
        positive(key("density"), m.density)?;
        let f = m.inertia_factor;
        if !(f.is_finite() && f > 0.0 && f <= 1.0) {
            return Err(SetupError::new(
                key("inertia_factor"),
                f,
                "must be in (0, 1]",
            ));
        }
        let required = matches!(model, ContactModel::Material { .. });
        let need = |field: &str, v: Option<f64>| -> Result<Option<f64>, SetupError> {
            match v {
                None if required => Err(SetupError::new(
                    key(field),
                    "(missing)",
                    "required by contact model \"material\"",
                )),
                other => Ok(other),
            }
        };
        if let Some(y) = need("youngs", m.youngs)? {
            positive(key("youngs"), y)?;
        }
        if let Some(nu) = need("poisson", m.poisson)? {
            if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
                return Err(SetupError::new(key("poisson"), nu, "must be in (-1, 0.5)"));
            }
        }
        if let Some(e) = need("restitution", m.restitution)? {
            if !(e.is_finite() && e > 0.0 && e <= 1.0) {
                return Err(SetupError::new(key("restitution"), e, "must be in (0, 1]"));
            }
        }
        if let Some(mu) = need("friction", m.friction)? {
            if !(mu.is_finite() && mu >= 0.0) {
                return Err(SetupError::new(
                    key("friction"),
                    mu,
                    "must be a finite number >= 0",
                ));
            }
        }
    }
    if let ContactModel::HookeHistory {
        kn,
        kt,
        gamma_n,
        gamma_t,
        mu,
        ..
    } = *model
    {
        positive("contact.kn".into(), kn)?;
        positive("contact.kt".into(), kt)?;
        for (k, v) in [
            ("contact.gamma_n", gamma_n),
            ("contact.gamma_t", gamma_t),
            ("contact.mu", mu),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(SetupError::new(k, v, "must be a finite number >= 0"));
            }
        }
    }
    Ok(())
}

impl Setup {
    /// Builds the pair table from validated materials and model.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        domain: Domain,
        materials: Vec<Material>,
        model: ContactModel,
        walls: Vec<Wall>,
        gravity: DVec2,
        dt: f64,
        skin: f64,
    ) -> Result<Self, SetupError> {
        validate_materials(&model, &materials)?;
        if walls.len() > MAX_WALLS {
            return Err(SetupError::new(
                "wall",
                format!("{} walls", walls.len()),
                format!("at most {MAX_WALLS} walls"),
            ));
        }
        let l = domain.length();
        if !(l.x > 0.0 && l.y > 0.0 && l.is_finite()) {
            return Err(SetupError::new(
                "domain",
                format!("lo = {:?}, hi = {:?}", domain.lo, domain.hi),
                "hi must exceed lo on both axes",
            ));
        }
        positive("run.skin".into(), skin)?;
        positive("run.dt".into(), dt)?;
        let pairs = PairTable::new(&model, &materials);
        Ok(Setup {
            domain,
            materials,
            model,
            pairs,
            walls,
            gravity,
            dt,
            skin,
        })
    }

    /// Contact parameters between a particle of material `mat` and wall `w`.
    #[inline(always)]
    pub fn wall_pair(&self, w: usize, mat: usize) -> &crate::contact::PairParams {
        let wm = self.walls[w].material.map_or(mat, |m| m as usize);
        self.pairs.get(mat, wm)
    }
}
