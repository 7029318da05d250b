//! What a run remembers to judge itself: wall impacts of each body (from the contact
//! flags of every step), sampled energies and body motion (every history row), and the
//! checks computed from them at the end.

use super::scenario::{CheckSpec, InclineMotion};
use glam::DVec2;
use grains_core::checks::Check;
use grains_mpm::setup::SIDES;
use grains_mpm::{ContactLaw, Geometry, Setup};

/// Steps without wall contact that end an impact (contact on the grid flickers).
const QUIET_STEPS: u64 = 20;

/// One wall impact of a body.
#[derive(Clone, Debug, PartialEq)]
pub struct Impact {
    /// First step time with wall contact (s).
    pub start: f64,
    /// Last step time with wall contact (s), once the impact is over.
    pub end: Option<f64>,
    /// Walls touched (bit per side).
    pub walls: u8,
    last_step: u64,
}

/// One body at one history row.
#[derive(Clone, Copy, Debug, Default)]
pub struct BodySample {
    /// Centre of mass.
    pub centre: DVec2,
    /// Centre-of-mass velocity.
    pub velocity: DVec2,
    /// Angular velocity.
    pub omega: f64,
    /// Accumulated rotation (rad).
    pub angle: f64,
    /// Mean in-plane stress (σ_xx + σ_yy)/2 of its points (Pa).
    pub mean_stress: f64,
    /// Debonded length of its bonded interfaces (m; 0 without a bond).
    pub debonded: f64,
    /// Its perimeter as the grid sees it (m; 0 without a bond).
    pub surface: f64,
    /// A rigid body: the mean force it exerted on the material since the previous row
    /// (N per unit thickness).
    pub force: DVec2,
    /// A rigid body: how far its prescribed velocity has moved it (m).
    pub displacement: DVec2,
}

/// One history row.
#[derive(Clone, Debug, Default)]
pub struct Sample {
    /// Time.
    pub t: f64,
    /// Kinetic + strain + potential energy.
    pub energy: f64,
    /// The ledger: energy + dissipated − thermal work.
    pub balance: f64,
    /// Energy dissipated by plasticity and viscosity so far.
    pub dissipated: f64,
    /// Work of the thermal strains so far.
    pub thermal_work: f64,
    /// Total momentum of the free bodies.
    pub momentum: DVec2,
    /// Per body.
    pub bodies: Vec<BodySample>,
    /// Plastic work of the J2 bodies so far.
    pub plastic: f64,
    /// Viscous dissipation of the Maxwell bodies so far.
    pub viscous: f64,
    /// Kinetic energy taken out by Coulomb contacts and walls so far.
    pub friction: f64,
    /// Kinetic energy taken out where bonds hold or fail so far.
    pub bond: f64,
    /// Work of the rigid bodies on the material so far.
    pub work: f64,
    /// Energy the grid-to-point transfer lost so far (numerical).
    pub transfer: f64,
}

impl Sample {
    /// The whole ledger: energy + plastic + viscous + friction + bond + transfer −
    /// thermal work − boundary work; constant up to the stress update's own error.
    pub fn ledger(&self) -> f64 {
        self.energy + self.dissipated + self.friction + self.bond + self.transfer
            - self.thermal_work
            - self.work
    }
}

/// The record of a run.
#[derive(Clone, Debug, Default)]
pub struct Record {
    /// Impacts per body.
    pub impacts: Vec<Vec<Impact>>,
    /// History rows.
    pub samples: Vec<Sample>,
}

impl Record {
    /// An empty record for `bodies` bodies.
    pub fn new(bodies: usize) -> Self {
        Record {
            impacts: vec![Vec::new(); bodies],
            samples: Vec::new(),
        }
    }

    /// Looks at the wall contacts of a step.
    pub fn step(&mut self, step: u64, t: f64, walls: impl Iterator<Item = u8>) {
        for (list, mask) in self.impacts.iter_mut().zip(walls) {
            let open = list.last_mut().filter(|i| i.end.is_none());
            match (open, mask != 0) {
                (Some(i), true) => {
                    i.walls |= mask;
                    i.last_step = step;
                    i.end = None;
                }
                (Some(i), false) => {
                    if step - i.last_step >= QUIET_STEPS {
                        i.end = Some(t);
                    }
                }
                (None, true) => list.push(Impact {
                    start: t,
                    end: None,
                    walls: mask,
                    last_step: step,
                }),
                (None, false) => {}
            }
        }
    }

    /// True while body `b` is in an impact.
    pub fn in_impact(&self, b: usize) -> bool {
        self.impacts[b].last().is_some_and(|i| i.end.is_none())
    }

    /// Rows of body `b`'s free flight after impact `k` (0: before the first), until the
    /// next impact starts; `None` if impact `k` never ended.
    pub fn window(&self, b: usize, k: usize) -> Option<Vec<&Sample>> {
        let list = &self.impacts[b];
        let from = if k == 0 {
            f64::NEG_INFINITY
        } else {
            list.get(k - 1)?.end?
        };
        let to = list.get(k).map_or(f64::INFINITY, |i| i.start);
        Some(
            self.samples
                .iter()
                .filter(|s| s.t > from && s.t < to)
                .collect(),
        )
    }

    /// Mean of `f` over a window, NaN if it is empty.
    fn mean(rows: &[&Sample], f: impl Fn(&Sample) -> f64) -> f64 {
        rows.iter().map(|s| f(s)).sum::<f64>() / rows.len() as f64
    }

    /// Total rotation of body `b` within each free-flight window (degrees).
    pub fn rotation_per_window(&self, b: usize) -> Vec<f64> {
        (0..=self.impacts[b].len())
            .filter_map(|k| self.window(b, k))
            .filter(|w| w.len() > 1)
            .map(|w| (w[w.len() - 1].bodies[b].angle - w[0].bodies[b].angle).to_degrees())
            .collect()
    }

    /// Mean |Σ m v| over the free flight after impact `k` of body 0's record, NaN if none.
    pub fn momentum_after(&self, k: usize) -> f64 {
        (0..self.impacts.len())
            .find_map(|b| self.window(b, k).filter(|w| !w.is_empty()))
            .map_or(f64::NAN, |w| Self::mean(&w, |s| s.momentum.length()))
    }

    /// Mean centre-of-mass velocity of body `b` over a window.
    fn mean_velocity(rows: &[&Sample], b: usize) -> DVec2 {
        DVec2::new(
            Self::mean(rows, |s| s.bodies[b].velocity.x),
            Self::mean(rows, |s| s.bodies[b].velocity.y),
        )
    }

    /// Impact `k` (from 1) of body `b` as seen from the free flights before and after
    /// it: `None` until it has ended and both flights hold samples.
    pub fn bounce(&self, b: usize, k: usize) -> Option<Bounce> {
        let hit = self.impacts[b].get(k.checked_sub(1)?)?;
        let (before, after) = (self.window(b, k - 1)?, self.window(b, k)?);
        if before.is_empty() || after.is_empty() {
            return None;
        }
        let side = (hit.walls.trailing_zeros() as usize).min(3);
        let n = [DVec2::NEG_X, DVec2::X, DVec2::NEG_Y, DVec2::Y][side];
        let (v0, v1) = (
            Self::mean_velocity(&before, b),
            Self::mean_velocity(&after, b),
        );
        let t = n.perp();
        // Relative to the momentum along the wall, or to the whole momentum when the body
        // came in square to the wall.
        let scale = v0.dot(t).abs().max(1e-6 * v0.length());
        Some(Bounce {
            side,
            restitution: -v1.dot(n) / v0.dot(n),
            tangential_change: (v1.dot(t) - v0.dot(t)) / scale,
        })
    }

    /// Energy lost by the end of impact `k` as a fraction of the initial energy, from
    /// the mean over the free flight that follows.
    pub fn energy_loss(&self, b: usize, k: usize) -> f64 {
        let e0 = self.samples.first().map_or(f64::NAN, |s| s.energy);
        self.window(b, k)
            .map_or(f64::NAN, |w| (e0 - Self::mean(&w, |s| s.energy)) / e0)
    }
}

/// A wall impact judged from the free flights on either side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounce {
    /// The wall hit (index into `SIDES`).
    pub side: usize,
    /// Normal restitution −v_n(after)/v_n(before) of the centre of mass.
    pub restitution: f64,
    /// Change of the momentum along the wall, as a fraction of it (signed).
    pub tangential_change: f64,
}

fn relative(name: &str, m: f64, e: f64, tol: f64, note: Option<String>) -> Check {
    let c = Check::relative(name, m, e, tol);
    match note {
        Some(n) => c.with_note(&n),
        None => c,
    }
}

/// Rigid-disk impulse theory for an elastic (e = 1) wall impact with Coulomb friction:
/// (tangential velocity, spin) after, from (velocity, spin) before.
pub fn disk_impact(v: DVec2, w: f64, n: DVec2, radius: f64, mu: f64) -> (f64, f64, DVec2) {
    let vn = v.dot(n);
    let mut t = n.perp();
    if v.dot(t) < 0.0 {
        t = -t;
    }
    let arm = radius * n;
    let slip = (v + w * arm.perp()).dot(t);
    // Per unit mass: normal impulse 2 vn; stopping the slip takes slip / 3 for a disk.
    let j = -slip.signum() * (mu * 2.0 * vn.abs()).min(slip.abs() / 3.0);
    let inertia = 0.5 * radius * radius;
    (v.dot(t) + j, w + arm.perp_dot(t) * j / inertia, t)
}

/// Least-squares fit of s(t) = s0 + v0 t + a t²/2; returns a.
pub fn fit_acceleration(t: &[f64], s: &[f64]) -> f64 {
    let n = t.len() as f64;
    if t.len() < 3 {
        return f64::NAN;
    }
    let t0 = t.iter().sum::<f64>() / n;
    // Normal equations in (1, τ, τ²) with τ = t − mean, for conditioning.
    let mut m = [[0.0f64; 3]; 3];
    let mut r = [0.0f64; 3];
    for (ti, si) in t.iter().zip(s) {
        let tau = ti - t0;
        let b = [1.0, tau, tau * tau];
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] += b[i] * b[j];
            }
            r[i] += b[i] * si;
        }
    }
    // Cramer's rule for the τ² coefficient c: a = 2c.
    let det = |a: [[f64; 3]; 3]| {
        a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
            - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
    };
    let mut m2 = m;
    for i in 0..3 {
        m2[i][2] = r[i];
    }
    2.0 * det(m2) / det(m)
}

/// Everything the checks need besides the record.
pub struct Context<'a> {
    /// Engine set-up.
    pub setup: &'a Setup,
    /// Body shapes.
    pub geometry: Vec<&'a Geometry>,
    /// Expected initial energy and momentum from the exact shapes.
    pub exact: (f64, DVec2),
    /// Measured initial (kinetic + strain) energy and momentum.
    pub initial: (f64, DVec2),
}

/// Turns the record into the scenario's checks (except reference comparisons).
pub fn checks(rec: &Record, cx: &Context, specs: &[CheckSpec]) -> Vec<Option<Check>> {
    let body = |name: &str| {
        cx.setup
            .bodies
            .iter()
            .position(|b| b.name == name)
            .expect("validated")
    };
    specs
        .iter()
        .map(|spec| {
            Some(match spec {
                CheckSpec::InitialEnergy { name, tolerance } => {
                    Check::relative(name, cx.initial.0, cx.exact.0, *tolerance)
                        .with_note("Σ ½ m v² + strain energy at t = 0 vs ½ ρ A |v|² of the exact shapes")
                }
                CheckSpec::InitialMomentum { name, component, tolerance } => {
                    let k = if component == "x" { 0 } else { 1 };
                    Check::relative(name, cx.initial.1[k], cx.exact.1[k], *tolerance)
                        .with_note("Σ m v at t = 0 vs ρ A v of the exact shapes")
                }
                CheckSpec::EnergyLoss { name, body: b, after_impact, max } => {
                    let loss = rec.energy_loss(body(b), *after_impact);
                    let c = Check::absolute(name, loss, 0.0, *max);
                    if loss.is_nan() {
                        c.with_note(&format!("impact {after_impact} did not end within the run"))
                    } else {
                        c.with_note("(E0 − mean E over the free flight after the impact) / E0, E = kinetic + strain (+ potential); two-sided: a gain fails as a loss does")
                    }
                }
                CheckSpec::TangentialMomentumChange { name, body: b, max } => {
                    let b = body(b);
                    let changes: Vec<f64> = (1..=rec.impacts[b].len())
                        .filter_map(|k| rec.bounce(b, k))
                        .map(|x| x.tangential_change.abs())
                        .collect();
                    let worst = if changes.is_empty() {
                        f64::NAN
                    } else {
                        changes.iter().copied().fold(0.0, f64::max)
                    };
                    Check::at_most(name, worst, *max).with_note(&format!(
                        "largest |Δ(m v·t)| / |m v·t| over {} completed wall impacts, v the centre-of-mass velocity averaged over the free flights before and after, t along the wall: a frictionless wall exerts no tangential impulse",
                        changes.len()
                    ))
                }
                CheckSpec::Rotation { name, body: b, max_deg } => {
                    let a = rec.samples.last().map_or(f64::NAN, |s| s.bodies[body(b)].angle);
                    Check::at_most(name, a.to_degrees().abs(), *max_deg)
                        .with_note("accumulated best-fit rotation of the body's points (degrees)")
                }
                CheckSpec::ImpactTangentialVelocity { name, body: b, impact, tolerance }
                | CheckSpec::ImpactSpin { name, body: b, impact, tolerance } => {
                    let bi = body(b);
                    let Geometry::Disk { radius, .. } = cx.geometry[bi] else {
                        return Some(Check::relative(name, f64::NAN, f64::NAN, *tolerance).with_note("the body must be a disk"));
                    };
                    let (Some(before), Some(after), Some(hit)) =
                        (rec.window(bi, impact - 1), rec.window(bi, *impact), rec.impacts[bi].get(impact - 1))
                    else {
                        return Some(Check::relative(name, f64::NAN, f64::NAN, *tolerance).with_note("the impact did not complete within the run"));
                    };
                    let side = hit.walls.trailing_zeros() as usize;
                    let n = [DVec2::NEG_X, DVec2::X, DVec2::NEG_Y, DVec2::Y][side.min(3)];
                    let mu = cx.setup.walls[side.min(3)].unwrap_or(0.0);
                    let v0 = DVec2::new(
                        Record::mean(&before, |s| s.bodies[bi].velocity.x),
                        Record::mean(&before, |s| s.bodies[bi].velocity.y),
                    );
                    let w0 = Record::mean(&before, |s| s.bodies[bi].omega);
                    let (vt, w, t) = disk_impact(v0, w0, n, *radius, mu);
                    let note = Some(format!(
                        "impact {impact} on the {} wall (μ = {mu}); rigid disk, e = 1; means over the free flights before and after",
                        SIDES[side.min(3)]
                    ));
                    if matches!(spec, CheckSpec::ImpactSpin { .. }) {
                        relative(name, Record::mean(&after, |s| s.bodies[bi].omega), w, *tolerance, note)
                    } else {
                        relative(name, Record::mean(&after, |s| s.bodies[bi].velocity.dot(t)), vt, *tolerance, note)
                    }
                }
                CheckSpec::Acceleration { name, body: b, on, normal, motion, after, tolerance } => {
                    let (bi, oi) = (body(b), body(on));
                    let n = DVec2::from(*normal).normalize();
                    let g = cx.setup.gravity;
                    let along = g - g.dot(n) * n;
                    let (gt, gn) = (along.length(), -g.dot(n));
                    let dir = along / gt;
                    let mu = match cx.setup.contact.get(bi, oi) {
                        ContactLaw::Coulomb { mu } | ContactLaw::Bonded { mu, .. } => mu,
                        ContactLaw::NoSlip => f64::INFINITY,
                    };
                    let slide = (gt - mu * gn).max(0.0);
                    let expected = match motion {
                        InclineMotion::Slide => slide,
                        InclineMotion::Roll if mu * gn >= gt / 3.0 => 2.0 * gt / 3.0,
                        InclineMotion::Roll => slide,
                    };
                    let rows: Vec<&Sample> = rec.samples.iter().filter(|s| s.t >= *after).collect();
                    let t: Vec<f64> = rows.iter().map(|s| s.t).collect();
                    let s: Vec<f64> = rows.iter().map(|s| s.bodies[bi].centre.dot(dir)).collect();
                    let theta = gt.atan2(gn).to_degrees();
                    relative(
                        name,
                        fit_acceleration(&t, &s),
                        expected,
                        *tolerance,
                        Some(format!(
                            "least-squares fit of the centre's position along the slope from t = {after}; θ = {theta:.3}°, μ = {mu}, g = {:.4}",
                            g.length()
                        )),
                    )
                }
                _ => return None,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rigid_disk_first_impact_numbers() {
        // The physics reference's case: v = (0.1, 0.1) onto the top wall, μ = 0.1.
        let (vt, w, _) = disk_impact(DVec2::new(0.1, 0.1), 0.0, DVec2::Y, 0.5, 0.1);
        assert!(
            (vt - 0.08).abs() < 1e-12 && (w - 0.08).abs() < 1e-12,
            "{vt} {w}"
        );
    }

    #[test]
    fn quadratic_fit() {
        let t: Vec<f64> = (0..50).map(|k| 1.0 + 0.1 * k as f64).collect();
        let s: Vec<f64> = t
            .iter()
            .map(|t| 2.0 - 0.5 * t + 0.5 * 3.3 * t * t)
            .collect();
        assert!((fit_acceleration(&t, &s) - 3.3).abs() < 1e-9);
    }

    #[test]
    fn impacts_end_after_quiet_steps() {
        let mut r = Record::new(1);
        for k in 0..100u64 {
            let m = if (10..30).contains(&k) && k != 20 {
                4
            } else {
                0
            };
            r.step(k, k as f64, [m].into_iter());
        }
        assert_eq!(r.impacts[0].len(), 1);
        assert_eq!(r.impacts[0][0].start, 10.0);
        assert_eq!(r.impacts[0][0].end, Some(49.0));
    }
}
