//! The whole protocol, one stage per step: line the walls, place the bulk disks on one
//! triangular lattice (or deposit them under gravity), grow them by hard-disk Monte
//! Carlo at the given rate until jammed, then swell and minimise the soft-disk energy
//! to close the last gaps.

use crate::deposit::deposit;
use crate::lattice::{clearance_factor, lattice_fill, template};
use crate::lining::lining;
use crate::mc::HardDisks;
use crate::relax::Soft;
use crate::sort::sort_sizes;
use crate::spec::{FinishSpec, PackSpec, ProtocolSpec, StartSpec};
use crate::validate::Validated;
use glam::DVec2;
use grains_analysis::fraction::bulk_fraction;
use grains_analysis::grid::CellGrid;
use grains_analysis::psi6::{order, psi6, OrderFigures};
use grains_analysis::region::Region;
use grains_analysis::INTERIOR_MARGIN_D0;
use grains_core::rng;
use rand::RngExt;
use std::time::Instant;

/// Disks drawn for deposition, relative to the number the region holds at φ = 0.92.
const DRAW_MARGIN: f64 = 1.05;
/// Sweeps between progress lines of the Monte Carlo stage.
const PROGRESS_EVERY: u64 = 1000;
/// Seconds between progress lines on long runs.
const PROGRESS_SECONDS: f64 = 60.0;
/// Sweeps between jamming tests of the Monte Carlo stage.
const STALL_WINDOW: u64 = 200;
/// Growth over a window, relative to the nominal `rate × window`, below which the
/// Monte Carlo stage counts as jammed.
const STALL_FRACTION: f64 = 0.25;
/// Force tolerance of each swell cycle and of the final minimisation (d0 units).
const FTOL_CYCLE: f64 = 1e-5;
const FTOL_FINAL: f64 = 1e-7;
/// Force tolerance of the overlap removal on the lattice start (d0 units).
const FTOL_START: f64 = 1e-7;
const ITER_CYCLE: u64 = 2000;
const ITER_FINAL: u64 = 20_000;
/// Energy per disk above which a swell cycle counts as jammed (overlaps ≳ 10⁻⁴ d0).
const JAM_ENERGY: f64 = 1e-8;

/// A finished packing in SI units; the first `lining` disks are the boundary layer.
#[derive(Clone, Debug)]
pub struct Packing {
    /// Centres (m).
    pub pos: Vec<DVec2>,
    /// Radii (m).
    pub radius: Vec<f64>,
    /// Number of leading boundary-layer disks.
    pub lining: usize,
    /// The container (m).
    pub region: Region,
    /// How the protocol went.
    pub stats: ProtocolStats,
}

/// Figures of the protocol's stages.
#[derive(Clone, Debug, Default)]
pub struct ProtocolStats {
    /// Bulk disks placed (lattice sites filled, or disks deposited).
    pub deposited: usize,
    /// Bulk packing fraction of the start at the drawn sizes (lattice) or as deposited.
    pub fraction_after_deposit: f64,
    /// Monte Carlo sweeps run.
    pub sweeps: u64,
    /// Bulk packing fraction when the Monte Carlo growth stopped.
    pub fraction_after_growth: f64,
    /// Acceptance of size exchanges, averaged over the sweeps.
    pub swap_acceptance: f64,
    /// Mean radius scale (relative to the drawn sizes) at the end.
    pub final_scale: f64,
    /// Swell cycles of the final minimisation.
    pub swell_cycles: u32,
    /// FIRE iterations in all.
    pub iterations: u64,
    /// Largest overlap left, relative to d0.
    pub max_overlap: f64,
    /// Bulk packing fraction at the end.
    pub fraction_bulk: f64,
    /// Probability mass the Gaussian loses at d ≤ 0.
    pub truncated_mass: f64,
    /// Wall time of the start, lattice or deposition (s).
    pub seconds_deposit: f64,
    /// Wall time of the Monte Carlo growth (s).
    pub seconds_growth: f64,
    /// Wall time of the swell-and-minimise stage (s).
    pub seconds_swell: f64,
}

/// What a packing reports as it goes: a line per stage, and how far it has got.
pub trait Watch {
    /// A line about a stage.
    fn line(&mut self, line: String);
    /// The share of the work done, 0 to 1 (an estimate while the growth runs).
    fn progress(&mut self, _done: f64) {}
}

impl<F: FnMut(String) + ?Sized> Watch for F {
    fn line(&mut self, line: String) {
        self(line)
    }
}

/// Share of the progress the start and the final swell take.
const PROGRESS_START: f64 = 0.02;
const PROGRESS_SWELL: f64 = 0.05;

/// The radius scale, relative to the drawn sizes, at which the growth ends with
/// `finish = "target"`: the bulk disks then fill `target_fraction` of the region inside
/// the lining, given that at their drawn sizes they would fill `spread` of it ([`spread`]),
/// capped at `1 + max_swell`. `None` when the growth goes on to jamming.
pub fn end_scale(p: &ProtocolSpec, spread: f64) -> Option<f64> {
    (p.finish == FinishSpec::Target).then(|| {
        (p.target_fraction / spread.max(1e-9))
            .sqrt()
            .min(1.0 + p.max_swell)
    })
}

/// The fraction of the region inside the lining (the region shrunk by the lining
/// disks' largest diameter) that disks of radii `radius` would fill: where a bulk
/// fraction ends once the disks have spread into every gap the start left, e.g.
/// between the lattice and the curved walls (`radius` in the region's units).
pub fn spread(region: &Region, radius: &[f64], lining_radius: f64) -> f64 {
    let area: f64 = radius.iter().map(|r| std::f64::consts::PI * r * r).sum();
    region
        .shrink(2.0 * lining_radius)
        .map_or(f64::NAN, |inner| area / inner.area())
}

/// Runs the protocol, reporting to `watch`.
pub fn pack(spec: &PackSpec, v: &Validated, watch: &mut dyn Watch) -> Packing {
    let d0 = v.d0;
    let p = &spec.protocol;
    // Work in units of d0 so tolerances are scale-free.
    let region = scale_region(&v.region, 1.0 / d0);
    let margin = INTERIOR_MARGIN_D0;
    let mut stats = ProtocolStats {
        truncated_mass: v.sizes.truncated_mass(),
        ..Default::default()
    };

    // 1. Lining and sizes.
    let phase = rng::stream(spec.seed, 1).random::<f64>();
    let lining_disks = lining(&region, spec.lining.diameter_ratio, phase);
    let fixed = lining_disks.len();
    let mut size_rng = rng::stream(spec.seed, 0);
    let mean_area = std::f64::consts::FRAC_PI_4 * v.sizes.mean_square() / (d0 * d0);
    let draw = (region.area() * 0.92 / mean_area * DRAW_MARGIN).ceil() as usize;
    watch.line(format!("lining: {fixed} disks"));

    // 2. The start: overlap-free bulk disks at `start_fraction`.
    let t0 = Instant::now();
    let (pos, base, s_start) = match p.start {
        StartSpec::Deposit => {
            let drawn: Vec<f64> = (0..draw)
                .map(|_| 0.5 * p.deposit_scale * v.sizes.sample(&mut size_rng) / d0)
                .collect();
            let dep = deposit(&region, &lining_disks, &drawn);
            stats.deposited = dep.pos.len();
            stats.fraction_after_deposit = bulk_fraction(&dep.pos, &dep.radius, &region, margin);
            watch.line(format!(
                "deposition: {} disks in {:.1} s, bulk fraction {:.4}",
                stats.deposited,
                t0.elapsed().as_secs_f64(),
                stats.fraction_after_deposit
            ));
            let order = spatial_order(&dep.pos, &region);
            let mut pos: Vec<DVec2> = lining_disks.iter().map(|l| l.0).collect();
            let mut base: Vec<f64> = lining_disks.iter().map(|l| l.1).collect();
            pos.extend(order.iter().map(|&k| dep.pos[k as usize]));
            base.extend(
                order
                    .iter()
                    .map(|&k| dep.radius[k as usize] / p.deposit_scale),
            );
            let s = (p.deposit_scale
                * (p.start_fraction / stats.fraction_after_deposit.max(1e-9)).sqrt())
            .min(p.deposit_scale);
            (pos, base, s)
        }
        StartSpec::Lattice => {
            let t = template(
                &region,
                &lining_disks,
                &v.sizes,
                d0,
                lattice_fill(p),
                spec.seed,
                &mut size_rng,
            );
            let (pos, mut base) = (t.pos, t.radius);
            let sites = pos.len() - fixed;
            stats.deposited = sites;
            stats.fraction_after_deposit = t.fraction;
            // Shrink to the start fraction, then push apart the few large neighbours
            // that still overlap: the lattice stays, slightly distorted.
            let s = (p.start_fraction / stats.fraction_after_deposit.max(1e-9))
                .sqrt()
                .min(1.0);
            if p.sort_sweeps > 0 {
                let st = sort_sizes(
                    &region,
                    &pos[fixed..],
                    &mut base[fixed..],
                    t.spacing,
                    s,
                    p.sort_sweeps,
                    spec.seed,
                );
                watch.line(format!(
                    "sort: {} sweeps, {} of {} exchanges kept; at {:.4} the lattice bonds' \
                     squared overlap falls to {:.0} % ({:.1} % of bonds overlap, {:.1} % before)",
                    p.sort_sweeps,
                    st.kept,
                    st.tried,
                    p.start_fraction,
                    100.0 * st.energy_after / st.energy_before.max(f64::MIN_POSITIVE),
                    100.0 * st.overlapping_after,
                    100.0 * st.overlapping_before
                ));
            }
            let rad: Vec<f64> = base
                .iter()
                .enumerate()
                .map(|(i, b)| if i < fixed { *b } else { b * s })
                .collect();
            let mut soft = Soft::new(pos, rad, fixed);
            let r = soft.minimise(&region, FTOL_START, ITER_FINAL);
            let f = clearance_factor(&region, &soft.pos, &soft.rad, fixed).min(1.0);
            watch.line(format!(
                "lattice: {} disks, bulk fraction {:.4} at full size; \
                 {} FIRE iterations to clear overlaps at {:.4}, in {:.1} s",
                sites,
                stats.fraction_after_deposit,
                r.iterations,
                p.start_fraction,
                t0.elapsed().as_secs_f64()
            ));
            (soft.pos, base, s * f * (1.0 - 1e-12))
        }
    };
    stats.seconds_deposit = t0.elapsed().as_secs_f64();

    watch.progress(PROGRESS_START);

    // 3. Monte Carlo growth from `start_fraction` until jammed (or at the target).
    let t1 = Instant::now();
    let mut scale = vec![1.0; fixed];
    scale.extend(std::iter::repeat_n(s_start, base.len() - fixed));
    let r_lining = base[..fixed].iter().copied().fold(0.0, f64::max);
    let target_scale = end_scale(p, spread(&region, &base[fixed..], r_lining));
    let mut hd = HardDisks::new(pos, base, scale, fixed, spec.seed);
    hd.swaps = p.swaps;
    let cap = target_scale.unwrap_or(1.0 + p.max_swell);
    // The sweeps the growth will take, for the progress estimate: to the target, or
    // to about where a lattice start jams.
    let growth_sweeps = ((target_scale.unwrap_or(crate::preview::JAMMED_SCALE) / s_start)
        .ln()
        .max(0.0)
        / p.rate.ln_1p())
    .max(1.0);
    let all_sweeps =
        (p.anneal_sweeps as f64 + growth_sweeps).min((p.anneal_sweeps + p.max_sweeps) as f64);
    let mut swap_sum = 0.0;
    let mut last_line = Instant::now();
    // The first `anneal_sweeps` sweeps hold the start fraction (no growth).
    let mut last = s_start;
    let mut last_min = s_start;
    let grown_from = p.anneal_sweeps;
    while hd.sweeps < p.anneal_sweeps + p.max_sweeps {
        let annealing = hd.sweeps < p.anneal_sweeps;
        let st = hd.sweep(&region, if annealing { 0.0 } else { p.rate }, cap);
        swap_sum += st.swap_acceptance;
        let done = if annealing {
            hd.sweeps as f64
        } else {
            p.anneal_sweeps as f64
                + growth_sweeps
                    * ((st.mean_scale / s_start).ln() / (growth_sweeps * p.rate.ln_1p()))
                        .clamp(0.0, 1.0)
        };
        watch.progress(
            PROGRESS_START + (1.0 - PROGRESS_START - PROGRESS_SWELL) * (done / all_sweeps).min(1.0),
        );
        if hd.sweeps.is_multiple_of(PROGRESS_EVERY)
            || last_line.elapsed().as_secs_f64() > PROGRESS_SECONDS
        {
            last_line = Instant::now();
            let (order, phi) = interior_order(&hd, &region, margin);
            watch.line(format!(
                "{}: sweep {} after {:.1} s, mean scale {:.5}, bulk fraction {:.4}, \
                 acceptance {:.2}, swaps {:.2}, interior psi6 local {:.3} global {:.3}",
                if annealing { "anneal" } else { "growth" },
                hd.sweeps,
                t1.elapsed().as_secs_f64(),
                st.mean_scale,
                phi,
                st.acceptance,
                st.swap_acceptance,
                order.local,
                order.global
            ));
        }
        if annealing {
            continue;
        }
        if st.min_scale >= cap - 1e-12 {
            break;
        }
        if (hd.sweeps - grown_from).is_multiple_of(STALL_WINDOW) {
            let nominal = (last * (1.0 + p.rate).powi(STALL_WINDOW as i32)).min(cap) - last;
            // Growing to a target, the last few disks held back by their neighbours
            // may still be catching up while the mean has arrived: that is no jam.
            let catching_up = target_scale.is_some() && st.min_scale > last_min;
            if st.mean_scale - last < STALL_FRACTION * nominal && !catching_up {
                break;
            }
            last = st.mean_scale;
            last_min = st.min_scale;
        }
    }
    stats.sweeps = hd.sweeps;
    stats.swap_acceptance = swap_sum / hd.sweeps.max(1) as f64;
    stats.seconds_growth = t1.elapsed().as_secs_f64();
    let (hd_pos, hd_base, hd_scale) = hd.state();
    let radii: Vec<f64> = hd_base.iter().zip(&hd_scale).map(|(b, s)| b * s).collect();
    stats.fraction_after_growth = bulk_fraction(&hd_pos, &radii, &region, margin);
    watch.line(format!(
        "growth: {} Monte Carlo sweeps in {:.1} s at rate {:e}, bulk fraction {:.4}",
        hd.sweeps, stats.seconds_growth, p.rate, stats.fraction_after_growth
    ));

    // 4. Swell and minimise: close the gaps hard-disk growth leaves at jamming. A
    // growth that reached its target leaves the disks as they are.
    let t2 = Instant::now();
    let reached = target_scale.is_some() && hd_scale[fixed..].iter().all(|s| *s >= cap - 1e-12);
    let current: Vec<f64> = radii[fixed..].to_vec();
    let mut soft = Soft::new(hd_pos, radii, fixed);
    let mut s = 1.0;
    let mut r = soft.minimise(&region, FTOL_CYCLE, ITER_CYCLE);
    stats.iterations += r.iterations;
    // With a target, a growth that stalled short of it swells up to it and no
    // further: the soft disks would otherwise press on to jamming, past the target.
    let bulk = (hd_scale.len() - fixed).max(1) as f64;
    let s_limit =
        target_scale.map(|_| (cap * bulk / hd_scale[fixed..].iter().sum::<f64>()).max(1.0));
    while !reached && stats.swell_cycles < 200 {
        let last = s_limit.filter(|&l| s * (1.0 + p.swell_step) >= l);
        let s_next = last.unwrap_or(s * (1.0 + p.swell_step));
        set_scale(&mut soft, &current, s_next);
        r = soft.minimise(&region, FTOL_CYCLE, ITER_CYCLE);
        stats.iterations += r.iterations;
        stats.swell_cycles += 1;
        if r.energy > JAM_ENERGY {
            set_scale(&mut soft, &current, s);
            break;
        }
        s = s_next;
        if last.is_some() {
            break;
        }
    }
    r = soft.minimise(&region, FTOL_FINAL, ITER_FINAL);
    stats.iterations += r.iterations;
    watch.progress(1.0);
    let sizes: Vec<f64> = soft.rad[fixed..].to_vec();
    let drawn_total: f64 = hd_base[fixed..].iter().sum();
    stats.final_scale = sizes.iter().sum::<f64>() / drawn_total.max(1e-300);
    stats.max_overlap = r.max_overlap;
    stats.fraction_bulk = bulk_fraction(&soft.pos, &soft.rad, &region, margin);
    stats.seconds_swell = t2.elapsed().as_secs_f64();
    watch.line(format!(
        "swell: {} cycles, {} FIRE iterations in {:.1} s; bulk fraction {:.4}, largest overlap {:.1e} d0",
        stats.swell_cycles, stats.iterations, stats.seconds_swell, stats.fraction_bulk, stats.max_overlap
    ));

    let wrap = |q: DVec2| match region {
        Region::Rectangle {
            lo,
            hi,
            periodic_x: true,
        } => DVec2::new(lo.x + (q.x - lo.x).rem_euclid(hi.x - lo.x), q.y),
        _ => q,
    };
    Packing {
        pos: soft.pos.iter().map(|q| wrap(*q) * d0).collect(),
        radius: soft.rad.iter().map(|r| r * d0).collect(),
        lining: fixed,
        region: v.region,
        stats,
    }
}

/// Interior ψ6 order and bulk fraction of the current hard-disk state: the progress
/// lines show how the template's order evolves as the disks grow.
fn interior_order(hd: &HardDisks, region: &Region, margin: f64) -> (OrderFigures, f64) {
    let (pos, base, scale) = hd.state();
    let radii: Vec<f64> = base.iter().zip(&scale).map(|(b, s)| b * s).collect();
    let (lo, hi) = region.bounds();
    let grid = CellGrid::build(&pos, lo, hi, 1.0, region.period_x());
    let psi = psi6(&pos, region, &grid);
    let fixed = hd.fixed;
    let order = order(&psi, |k| {
        k >= fixed && region.boundary_distance(pos[k]) >= margin
    });
    (order, bulk_fraction(&pos, &radii, region, margin))
}

fn set_scale(soft: &mut Soft, base: &[f64], s: f64) {
    let fixed = soft.fixed;
    for (r, b) in soft.rad[fixed..].iter_mut().zip(base) {
        *r = b * s;
    }
}

/// Indices of `pos` in cell order.
fn spatial_order(pos: &[DVec2], region: &Region) -> Vec<u32> {
    let (lo, hi) = region.bounds();
    CellGrid::build(pos, lo, hi, 4.0, region.period_x())
        .order()
        .to_vec()
}

/// The region with every length multiplied by `f`.
pub fn scale_region(r: &Region, f: f64) -> Region {
    match *r {
        Region::Annulus {
            centre,
            r_in,
            r_out,
        } => Region::Annulus {
            centre: centre * f,
            r_in: r_in * f,
            r_out: r_out * f,
        },
        Region::Disk { centre, radius } => Region::Disk {
            centre: centre * f,
            radius: radius * f,
        },
        Region::Rectangle { lo, hi, periodic_x } => Region::Rectangle {
            lo: lo * f,
            hi: hi * f,
            periodic_x,
        },
    }
}
