//! The DEM engine's reductions over MPI. Every reduction gathers each rank's values and
//! combines them in rank order on every rank, rather than calling `MPI_Allreduce`, whose
//! order of additions the standard leaves to the library: the result is then the same
//! on every rank and in every run on that many ranks.

use grains_dem::comm::Post;
use grains_dem::{Exchange, Reduce};
use mpi::datatype::PartitionMut;
use mpi::environment::Threading;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use mpi::Count;

/// The MPI world: initialised once per process and finalised when dropped (or when the
/// universe [`World::init_apart`] gave is).
pub struct World {
    // Dropped after `comm` (fields drop in order): finalises MPI.
    comm: SimpleCommunicator,
    _universe: Option<mpi::environment::Universe>,
}

// A run steps from a worker of the thread pool (rayon::scope), not from the thread that
// initialised MPI, so the world must move between threads, which rsmpi's communicator (a
// raw MPI handle) does not allow by itself.
// SAFETY: `init` only hands out a world when MPI granted MPI_THREAD_SERIALIZED or more,
// which allows calls from any thread as long as no two run at once; `World` is not
// `Sync`, so it is used by one thread at a time.
#[allow(unsafe_code)]
unsafe impl Send for World {}

impl World {
    /// Initialises MPI for calls from any one thread at a time; `None` if it already was
    /// in this process, or the library cannot serve calls from several threads.
    pub fn init() -> Option<World> {
        Self::init_apart().map(|(mut w, universe)| {
            w._universe = Some(universe);
            w
        })
    }

    /// [`World::init`], with MPI finalised when the caller drops the universe rather
    /// than the world: a caller can then speak after the run and before MPI_Finalize,
    /// which may not return while mpirun is stopping the job.
    pub fn init_apart() -> Option<(World, mpi::environment::Universe)> {
        let (universe, level) = mpi::initialize_with_threading(Threading::Serialized)?;
        if level < Threading::Serialized {
            return None;
        }
        let world = World {
            comm: universe.world(),
            _universe: None,
        };
        Some((world, universe))
    }

    /// Every rank's values, `values.len()` each, in rank order.
    fn all<T: Equivalence + Copy + Default>(&self, values: &[T]) -> Vec<T> {
        let mut out = vec![T::default(); values.len() * self.ranks()];
        self.comm.all_gather_into(values, &mut out[..]);
        out
    }

    /// Combines each rank's `values` element-wise, in rank order.
    fn fold<T: Equivalence + Copy + Default>(&self, values: &mut [T], op: impl Fn(T, T) -> T) {
        let n = values.len();
        let all = self.all(values);
        for (k, v) in values.iter_mut().enumerate() {
            *v = (0..self.ranks())
                .map(|r| all[r * n + k])
                .reduce(&op)
                .unwrap_or(*v);
        }
    }

    /// Waits for every rank.
    pub fn barrier(&self) {
        self.comm.barrier();
    }
}

impl Reduce for World {
    fn ranks(&self) -> usize {
        self.comm.size() as usize
    }

    fn rank(&self) -> usize {
        self.comm.rank() as usize
    }

    fn sum(&self, values: &mut [f64]) {
        self.fold(values, |a, b| a + b);
    }

    fn sum_u64(&self, values: &mut [u64]) {
        self.fold(values, u64::wrapping_add);
    }

    fn max(&self, values: &mut [f64]) {
        // NaN wins, as a failed test must.
        self.fold(values, |a, b| if a.is_nan() || a > b { a } else { b });
    }

    fn gather(&self, words: Vec<u64>) -> Vec<u64> {
        let counts: Vec<Count> = self.all(&[words.len() as Count]);
        let displs: Vec<Count> = counts
            .iter()
            .scan(0, |at, &c| {
                let d = *at;
                *at += c;
                Some(d)
            })
            .collect();
        let total = counts.iter().map(|&c| c as usize).sum();
        let mut out = vec![0u64; total];
        let mut part = PartitionMut::new(&mut out[..], counts, &displs[..]);
        self.comm.all_gather_varcount_into(&words[..], &mut part);
        out
    }
}

/// A `World` by itself exchanges no particles: a decomposed run wraps it in
/// [`grains_dem::decomp::Decomposed`], which does, over [`Post`].
impl Exchange for World {}

/// Every send is posted at once (`MPI_Isend`), then the receives are taken in the
/// order asked, then the sends are waited for: no rank blocks on a send, whatever the
/// message sizes. Messages between two ranks arrive in the order sent (MPI's
/// non-overtaking rule), which is what the decomposition relies on.
impl Post for World {
    fn exchange(&self, outgoing: Vec<(usize, Vec<u8>)>, from: &[usize]) -> Vec<Vec<u8>> {
        mpi::request::scope(|scope| {
            let sends: Vec<_> = outgoing
                .iter()
                .map(|(to, bytes)| {
                    self.comm
                        .process_at_rank(*to as i32)
                        .immediate_send(scope, &bytes[..])
                })
                .collect();
            let got = from
                .iter()
                .map(|&q| self.comm.process_at_rank(q as i32).receive_vec::<u8>().0)
                .collect();
            for s in sends {
                s.wait();
            }
            got
        })
    }
}
