//! A FEM–DEM run spread over ranks (`mpirun -np N grains run`): every rank steps the
//! whole charge (it is small: thousands of elements) and its box of the ring, as a DEM
//! run's [`Part`]. The penalty pass gathers every rank's contacts with the charge's
//! edge and sums over them in one order (`grains_couple::hits`), so every rank applies
//! the same nodal forces and the charges stay equal bit for bit; each rank pushes the
//! grains it owns (docs/parallel.md, "The FEM–DEM ring on several ranks").

use crate::dem::ranks::{Link, Part};
use glam::DVec2;
use grains_couple::{coupled_step_by, Coupling, Ring};
use grains_dem::{Particles, Setup, State};
use grains_fem::stress::Breakdown;
use grains_fem::{Charge, FemSetup};

/// This rank's part of a coupled run.
pub struct RingPart {
    /// This rank's particles and ghosts, and the decomposition.
    pub part: Part,
    /// The ring's set-up without the expanding neighbour frame, which the decomposition
    /// does not carry: the list is rebuilt by the plain skin rule, and no force depends
    /// on when it was built (rule 1 of docs/parallel.md).
    setup: Setup,
    /// The charge's edge as this rank holds it: candidates among its own particles,
    /// the sums over every rank's contacts.
    pub coupling: Coupling,
    grid_box: (DVec2, DVec2),
}

impl RingPart {
    /// This rank's part of `ring` (the whole ring every rank assembled, or read back
    /// from a checkpoint) beside `charge`, on the grid `dims` (chosen when `None`) with
    /// load balancing past `balance`; one line naming what does not fit when it cannot be.
    pub fn new(
        link: Link,
        (ring, charge): (&Ring, &Charge),
        dims: Option<[usize; 2]>,
        balance: Option<f64>,
    ) -> Result<RingPart, String> {
        let mut setup = ring.setup.clone();
        setup.expanding_from = None;
        let part = Part::new(link, &setup, &ring.state, dims, (balance, 0.0))?;
        let mut coupling = ring.coupling.clone();
        if part.ranks() > 1 {
            // The part is in a new order, its list just built; one rank keeps the
            // ring as it is, candidates and all.
            candidates_for(&mut coupling, charge, &part.local.particles);
        }
        Ok(RingPart {
            part,
            setup,
            coupling,
            grid_box: ring.grid_box,
        })
    }

    /// One coupled step of the charge and this rank's part; `view` (rank 0's whole
    /// state between gathers) takes what every rank knows ([`Part::advance`]).
    pub fn advance(
        &mut self,
        (fem, charge): (&FemSetup, &mut Charge),
        dt: f64,
        outside: &mut dyn FnMut(&mut Particles),
        view: &mut State,
    ) -> Result<(), Breakdown> {
        let (part, setup) = (&mut self.part, &self.setup);
        let (coupling, grid_box) = (&mut self.coupling, &mut self.grid_box);
        coupled_step_by(fem, charge, coupling, grid_box, dt, outside, |edge| {
            part.advance_with(setup, dt, edge, view)
        })
    }

    /// Gathers the whole ring into rank 0's `view` (its candidates made again for the
    /// gathered order, as a checkpoint holds them) and takes the state hash over every
    /// rank.
    pub fn gather(&mut self, charge: &Charge, view: &mut Ring) {
        self.part.gather(&self.setup, &mut view.state);
        if self.part.rank() == 0 {
            view.coupling = self.coupling.clone();
            candidates_for(&mut view.coupling, charge, &view.state.particles);
            view.grid_box = self.grid_box;
        }
    }

    /// The ring's set-up on the ranks.
    pub fn setup(&self) -> &Setup {
        &self.setup
    }
}

/// Makes `coupling`'s candidates again for `particles` (the ring's grains in another
/// order, or a rank's part of them), as right after a neighbour list is built, keeping
/// its count of detections (a figure of the run).
fn candidates_for(coupling: &mut Coupling, charge: &Charge, particles: &Particles) {
    let builds = coupling.builds;
    coupling.rebuild_at(charge, particles, 0.0);
    coupling.builds = builds;
}
