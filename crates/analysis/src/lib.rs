//! Microstructure analysis of 2D disk packings, as in xue-2019 §3.
//!
//! Definitions (all documented for comparison with other tools):
//!
//! - **d0, δ**: mean diameter and polydispersity √⟨Δd²⟩/⟨d⟩ of the disks, leaving out
//!   the boundary-layer disks a packing file marks with its `# lining = N` header.
//! - **Interior**: particles whose centre is at least 2 d0 from every boundary of the
//!   region (periodic sides are not boundaries). The region comes from the file's
//!   `# domain = ...` header, or is the bounding box of the disks.
//! - **ψ6**: see [`psi6`]: 6 nearest neighbours by centre distance, no cut-off. Local
//!   order ⟨|ψ6(k)|⟩, global order |⟨ψ6(k)⟩|, each over all and over interior particles.
//! - **Contacts**: see [`contacts`]; coordination is the mean contact count of
//!   interior particles; the fabric uses every contact with an interior particle.
//! - **Bulk packing fraction**: disk area inside the region shrunk by 2 d0, over its area.
#![warn(missing_docs)]

pub mod contacts;
pub mod dispersal;
pub mod fraction;
pub mod grid;
pub mod psi6;
pub mod region;
pub mod ring;
pub mod rose;
pub mod sample;
pub mod sizes;

use contacts::{Contacts, Fabric};
use glam::DVec2;
use grid::CellGrid;
use psi6::OrderFigures;
use region::Region;
use sample::{Sample, SampleKind};
use sizes::SizeStats;

/// Margin defining interior particles and the bulk, in units of d0.
pub const INTERIOR_MARGIN_D0: f64 = 2.0;
/// Largest gap counted as a contact in a generated packing, in units of d0.
pub const PACKING_CONTACT_GAP_D0: f64 = 1e-3;
/// Sectors of the rose diagram.
pub const ROSE_BINS: usize = 72;

/// Everything `grains analyze` reports about a sample.
#[derive(Clone, Debug)]
pub struct Analysis {
    /// The region used (from the file or the bounding box).
    pub region: Region,
    /// Whether the region came from the file's header.
    pub region_from_file: bool,
    /// Size statistics of the non-lining disks.
    pub sizes: SizeStats,
    /// ψ6 per particle.
    pub psi6: Vec<DVec2>,
    /// Whether each particle is interior.
    pub interior: Vec<bool>,
    /// Order over all particles.
    pub order_all: OrderFigures,
    /// Order over interior particles.
    pub order_interior: OrderFigures,
    /// The contact network.
    pub contacts: Contacts,
    /// Gap threshold used for contacts (length units).
    pub contact_gap: f64,
    /// Mean contact count of interior particles.
    pub mean_coordination: f64,
    /// Fraction of interior particles with fewer than 3 contacts (rattlers in 2D).
    pub rattler_fraction: f64,
    /// Fabric of contacts touching an interior particle.
    pub fabric: Fabric,
    /// Rose-diagram density of those contacts' normals, [`ROSE_BINS`] sectors.
    pub rose: Vec<f64>,
    /// Packing fraction at least 2 d0 from every boundary.
    pub packing_fraction_bulk: f64,
    /// Packing fraction of the whole region.
    pub packing_fraction_total: f64,
}

/// Analyses a sample.
pub fn analyze(s: &Sample) -> Analysis {
    let (region, region_from_file) = match s.region {
        Some(r) => (r, true),
        None => (Region::bounding_box(&s.pos, &s.radius), false),
    };
    let diam: Vec<f64> = s.radius[s.lining.min(s.radius.len())..]
        .iter()
        .map(|r| 2.0 * r)
        .collect();
    let sizes = sizes::stats(&diam);
    let d0 = sizes.mean;
    let margin = INTERIOR_MARGIN_D0 * d0;
    let interior: Vec<bool> = s
        .pos
        .iter()
        .map(|p| region.boundary_distance(*p) >= margin)
        .collect();

    let (mut lo, mut hi) = region.bounds();
    for p in &s.pos {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let r_max = s.radius.iter().cloned().fold(0.0, f64::max);
    let contact_gap = match s.kind {
        SampleKind::Packing => PACKING_CONTACT_GAP_D0 * d0,
        SampleKind::DemFrame => 0.0,
    };
    let grid = CellGrid::build(&s.pos, lo, hi, 2.0 * r_max + contact_gap, region.period_x());
    let psi = psi6::psi6(&s.pos, &region, &grid);
    let order_all = psi6::order(&psi, |_| true);
    let order_interior = psi6::order(&psi, |k| interior[k]);

    let contacts = contacts::find(&s.pos, &s.radius, &region, &grid, contact_gap);
    let (mut z, mut n, mut rattlers) = (0u64, 0usize, 0usize);
    for (k, &c) in contacts.count.iter().enumerate() {
        if interior[k] {
            z += c as u64;
            n += 1;
            rattlers += (c < 3) as usize;
        }
    }
    let keep = |k: usize| {
        let (i, j) = contacts.pairs[k];
        interior[i as usize] || interior[j as usize]
    };
    let fabric = contacts::fabric(&contacts.normals, keep);
    let rose = contacts::rose(&contacts.normals, keep, ROSE_BINS);
    Analysis {
        region,
        region_from_file,
        sizes,
        interior,
        order_all,
        order_interior,
        mean_coordination: if n > 0 { z as f64 / n as f64 } else { f64::NAN },
        rattler_fraction: if n > 0 {
            rattlers as f64 / n as f64
        } else {
            f64::NAN
        },
        fabric,
        rose,
        packing_fraction_bulk: fraction::bulk_fraction(&s.pos, &s.radius, &region, margin),
        packing_fraction_total: fraction::packing_fraction(&s.pos, &s.radius, &region),
        contacts,
        contact_gap,
        psi6: psi,
    }
}
