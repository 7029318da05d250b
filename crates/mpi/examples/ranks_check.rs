//! The MPI checks, run by `.ci/run` under `mpirun -np 1`, `2` and `4`: the reductions
//! combine in rank order, the state hash of a run does not depend on how its particles
//! are spread over the ranks, and a decomposed run (migration, ghosts, messages over
//! MPI) of a column of disks that topples across the rank boundaries ends with the
//! serial run's hash. Exits 1 on any rank that finds a difference.

use glam::DVec2;
use grains_dem::decomp::Decomposed;
use grains_dem::diagnostics::{state_hash, state_hash_on};
use grains_dem::{step, step_on, NoHooks, Particles, Reduce, State};
use grains_mpi::World;

/// Twelve disks stacked in a zigzag at the middle of the peer benchmark's box, falling
/// and toppling: no disk ever touches three others, so every force is a sum of at most
/// two pair terms and the decomposed run can match the serial one bit for bit (with
/// more contacts the order of the sum differs: docs/parallel.md).
fn column() -> (grains_dem::Setup, State) {
    let setup = grains_sim::bench::dem::peer_setup(DVec2::ZERO, DVec2::new(40.0, 20.0));
    let mut p = Particles::default();
    for k in 0..12 {
        let x = 20.0 + if k % 2 == 0 { 0.07 } else { -0.07 };
        let at = DVec2::new(x, 6.0 + 1.05 * k as f64);
        p.push(at, 0.5, 1.0, 0.5, 0, DVec2::ZERO, 0.0);
    }
    let s = State::new(&setup, p);
    (setup, s)
}

/// The peer benchmark's bed of 600 disks after 1 s of settling: contacts with springs.
fn settled() -> State {
    let (setup, p) = grains_sim::bench::dem::peer_bed(600);
    let mut s = State::new(&setup, p);
    for _ in 0..2000 {
        step(&setup, &mut s, 5e-4);
    }
    s
}

fn main() {
    let world = World::init().expect("MPI initialised once");
    let (rank, ranks) = (world.rank(), world.ranks());
    let mut failures = Vec::new();

    // Sums in rank order: rank r adds 0.1·(r + 1), and 1e16 on rank 0, where the
    // order of additions shows in the last bits.
    let mut v = [if rank == 0 { 1e16 } else { 0.0 }, 0.1 * (rank + 1) as f64];
    world.sum(&mut v);
    let mut want = [0.0, 0.0];
    for r in 0..ranks {
        want[0] += if r == 0 { 1e16 } else { 0.0 };
        want[1] += 0.1 * (r + 1) as f64;
    }
    if v.map(f64::to_bits) != want.map(f64::to_bits) {
        failures.push(format!("sum {v:?}, want {want:?}"));
    }
    let mut m = [rank as f64, -(rank as f64)];
    world.max(&mut m);
    if m != [(ranks - 1) as f64, 0.0] {
        failures.push(format!("max {m:?}"));
    }
    let mut n = [rank as u64 + 1];
    world.sum_u64(&mut n);
    if n[0] != (ranks * (ranks + 1) / 2) as u64 {
        failures.push(format!("integer sum {n:?}"));
    }
    if !world.any(rank == ranks - 1) || world.any(false) {
        failures.push("any".into());
    }
    // Rank r sends r + 1 words, all r: every rank gets them all, in rank order.
    let got = world.gather(vec![rank as u64; rank + 1]);
    let want: Vec<u64> = (0..ranks as u64)
        .flat_map(|r| std::iter::repeat_n(r, r as usize + 1))
        .collect();
    if got != want {
        failures.push(format!("gather {got:?}"));
    }

    // Each rank owns every ranks-th particle of the same state: the gathered hash is
    // the serial one.
    let s = settled();
    let serial = state_hash(&s);
    let spread = state_hash_on(&s, &world, |i| s.particles.id[i] as usize % ranks == rank);
    if spread != serial {
        failures.push(format!("state hash {spread:016x}, serial {serial:016x}"));
    }
    let springs = s.contacts.shear.iter().filter(|x| **x != 0.0).count();
    if springs == 0 {
        failures.push("the bed has no springs to hash".into());
    }

    // The column, decomposed on the grid RankGrid::auto picks for this many ranks.
    let (setup, whole) = column();
    let mut alone = whole.clone();
    let steps = 6000;
    for _ in 0..steps {
        step(&setup, &mut alone, 5e-4);
    }
    let (world, column_line) = {
        let mut d = Decomposed::new(world, &setup, None, 0.5).expect("a grid for the column");
        let mut s = d.start(&setup, &whole);
        for _ in 0..steps {
            step_on(&setup, &mut s, 5e-4, &mut NoHooks, &mut d);
        }
        let (got, want) = (d.state_hash(&s), state_hash(&alone));
        if got != want {
            failures.push(format!(
                "decomposed column {:?}: hash {got:016x}, serial {want:016x}",
                d.grid().dims
            ));
        }
        let line = format!("column on {:?}: {got:016x}", d.grid().dims);
        (d.into_inner(), line)
    };

    world.barrier();
    if failures.is_empty() {
        println!(
            "rank {rank} of {ranks}: ok (state hash {serial:016x}, {springs} springs; {column_line})"
        );
    } else {
        for f in &failures {
            eprintln!("rank {rank} of {ranks}: {f}");
        }
        drop(world);
        std::process::exit(1);
    }
}
