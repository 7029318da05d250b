//! The read-only description of a DEM run that every stage reads: domain, walls,
//! contact table, gravity and neighbour skin.

use crate::contact::{ContactModel, PairTable};
use crate::domain::Domain;
use crate::granular::GranularParams;
use crate::material::Material;
use crate::math::Vector;
use crate::walls::Wall;
use grains_core::input::InputError;

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
    pub gravity: Vector,
    /// Verlet skin (m): pairs closer than r_i + r_j + skin are listed, and the list is
    /// rebuilt once any particle has moved more than skin/2 (in the frame below, if any).
    pub skin: f64,
    /// The point the particles spread from, when they do (an explosive ring): the list
    /// is then judged in a frame that expands from it ([`crate::verlet`]); `None`: the
    /// classic rule.
    pub expanding_from: Option<Vector>,
    /// The law of LAMMPS `pair granular` per material pair ([`crate::granular`]), which
    /// then replaces the linear law of `pairs` for every pair and wall; `None`: the
    /// linear law. Set through the library and by 3D scenarios. The stable time step
    /// ([`crate::timestep`]), `diagnostics::measure` and `stress` ask this law
    /// ([`crate::law::ContactLaw`]); it keeps no energy ledger.
    pub granular: Option<PairTable<GranularParams>>,
}

/// Walls are tracked per particle in a 64-bit mask of nearby walls.
pub const MAX_WALLS: usize = 64;

fn positive(key: String, v: f64) -> Result<(), InputError> {
    grains_core::input::positive(&key, v)
}

/// Checks that every material carries what the contact model needs, in range.
pub fn validate_materials(model: &ContactModel, materials: &[Material]) -> Result<(), InputError> {
    // The material route's stiffness is 2D's (N/m per unit thickness from Y); its 3D
    // form (K_n = π R_eff Y_eff) depends on the pair's radii, which the per-material
    // table does not know.
    #[cfg(feature = "dim3")]
    if let ContactModel::Material { .. } = model {
        return Err(InputError::new(
            "contact.model",
            "material",
            "in 3D, \"hooke_history\" (the 3D material law is not available yet)",
        ));
    }
    for m in materials {
        let key = |f: &str| format!("material.{}.{}", m.name, f);
        positive(key("density"), m.density)?;
        let f = m.inertia_factor;
        if !(f.is_finite() && f > 0.0 && f <= 1.0) {
            return Err(InputError::new(
                key("inertia_factor"),
                f,
                "must be in (0, 1]",
            ));
        }
        let required = matches!(model, ContactModel::Material { .. });
        let need = |field: &str, v: Option<f64>| -> Result<Option<f64>, InputError> {
            match v {
                None if required => Err(InputError::new(
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
                return Err(InputError::new(key("poisson"), nu, "must be in (-1, 0.5)"));
            }
        }
        if let Some(e) = need("restitution", m.restitution)? {
            if !(e.is_finite() && e > 0.0 && e <= 1.0) {
                return Err(InputError::new(key("restitution"), e, "must be in (0, 1]"));
            }
        }
        if let Some(mu) = need("friction", m.friction)? {
            if !(mu.is_finite() && mu >= 0.0) {
                return Err(InputError::new(
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
                return Err(InputError::new(k, v, "must be a finite number >= 0"));
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
        gravity: Vector,
        skin: f64,
    ) -> Result<Self, InputError> {
        validate_materials(&model, &materials)?;
        if walls.len() > MAX_WALLS {
            return Err(InputError::new(
                "wall",
                format!("{} walls", walls.len()),
                format!("at most {MAX_WALLS} walls"),
            ));
        }
        let l = domain.length();
        if !((0..crate::math::DIM).all(|a| l[a] > 0.0) && l.is_finite()) {
            return Err(InputError::new(
                "domain",
                format!("lo = {:?}, hi = {:?}", domain.lo, domain.hi),
                "hi must exceed lo on every axis",
            ));
        }
        positive("run.skin".into(), skin)?;
        let pairs = PairTable::new(&model, &materials);
        Ok(Setup {
            domain,
            materials,
            model,
            pairs,
            walls,
            gravity,
            skin,
            expanding_from: None,
            granular: None,
        })
    }

    /// Contact parameters between a particle of material `mat` and wall `w`.
    #[inline(always)]
    pub fn wall_pair(&self, w: usize, mat: usize) -> &crate::contact::PairParams {
        let wm = self.walls[w].material.map_or(mat, |m| m as usize);
        self.pairs.get(mat, wm)
    }
}
