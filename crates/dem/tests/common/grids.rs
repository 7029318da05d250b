// Runs of a state on several grids of in-process ranks, for the decomposition tests of
// both builds (2D: `crates/dem/tests/decomposition.rs`; 3D: `crates/dem3d/tests`).

#[cfg(feature = "dim3")]
use grains_dem3d as dem;

#[cfg(not(feature = "dim3"))]
use grains_dem as dem;

use dem::decomp::local::{run_ranks, Local};
use dem::decomp::Decomposed;
use dem::math::DIM;
use dem::{step_on, NoHooks, Setup, State};

/// A pool of `t` threads.
pub fn pool(t: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(t)
        .build()
        .unwrap()
}

/// Runs `whole` for `steps` steps of `dt` on each grid of in-process ranks (at its
/// number of threads per rank), and checks what `record` takes every `every` steps
/// against the serial run's, `want`, on every rank. Returns, per grid and rank, the
/// most particles (owned and ghosts) the rank held.
pub fn on_grids<T: PartialEq + std::fmt::Debug + Send>(
    set: &Setup,
    whole: &State,
    (dt, steps, every): (f64, usize, usize),
    grids: &[([usize; DIM], usize)],
    want: &[T],
    record: impl Fn(&Decomposed<Local>, &State) -> T + Sync,
) -> Vec<Vec<usize>> {
    let r_max = whole.particles.radius.iter().fold(0.0f64, |a, &r| a.max(r));
    let mut held = Vec::new();
    for &(dims, threads) in grids {
        let ranks = dims.iter().product();
        let out = run_ranks(ranks, |l| {
            pool(threads).install(|| {
                let mut d = Decomposed::new(l, set, Some(dims), r_max).unwrap();
                let mut s = d.start(set, whole);
                let (mut hs, mut most) = (Vec::new(), 0);
                for k in 0..steps {
                    step_on(set, &mut s, dt, &mut NoHooks, &mut d);
                    if k % every == every - 1 {
                        hs.push(record(&d, &s));
                    }
                    most = most.max(s.particles.len());
                }
                (hs, most)
            })
        });
        for (r, (hs, _)) in out.iter().enumerate() {
            assert_eq!(hs, want, "{dims:?}, {threads} threads, rank {r}");
        }
        held.push(out.into_iter().map(|o| o.1).collect());
    }
    held
}
