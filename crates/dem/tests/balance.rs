//! Load balancing of the domain decomposition on in-process ranks: the cuts move to the
//! particles, the particles go to their new ranks with their springs, and the run stays
//! the serial run bit for bit.

use glam::DVec2;
use grains_dem::decomp::local::{run_ranks, Local};
use grains_dem::decomp::Decomposed;
use grains_dem::diagnostics::state_hash;
use grains_dem::{step, step_on, Domain, Exchange, NoHooks, Particles, Setup, State};

#[path = "common/peer.rs"]
mod peer;

/// A closed-bottom box 48 × 24 (open sides and top), the floor, unit gravity.
fn corner_setup() -> Setup {
    let domain = Domain {
        lo: DVec2::ZERO,
        hi: DVec2::new(48.0, 24.0),
        periodic: [false, false],
    };
    let (material, model) = (peer::material(), peer::hooke(4000.0, 87.0));
    Setup::new(
        domain,
        vec![material],
        model,
        vec![peer::floor()],
        DVec2::new(0.0, -1.0),
        0.1,
    )
    .unwrap()
}

/// 400 disks squeezed on a triangular lattice 20 wide in the lower left corner (each
/// overlaps up to six neighbours), thrown to the right at 24 m/s and spreading from
/// their centre at 0.5 /s: they spring apart, bounce on the floor and cross the box,
/// leaving the corner empty.
fn lump() -> Particles {
    let (_, mut p) = peer::bed(400, 20);
    let centre = DVec2::new(9.5, 8.0);
    for (k, (x, v)) in p.pos.iter_mut().zip(p.vel.iter_mut()).enumerate() {
        let (row, col) = ((k / 20) as f64, (k % 20) as f64);
        let shift = 0.5 * ((k / 20) % 2) as f64;
        *x = 0.95 * DVec2::new(col + 0.5 + shift, 0.866 * row + 0.6);
        *v = DVec2::new(24.0, 0.0) + 0.5 * (*x - centre);
    }
    p
}

/// What one rank saw of a run: the state hash every `EVERY` steps, the imbalance at the
/// start and the worst after any rebuild, the rebalances, and its particles at the end.
#[derive(Debug)]
struct Seen {
    hashes: Vec<u64>,
    start: f64,
    worst: f64,
    rebalances: u64,
    owned: [usize; 2],
}

const STEPS: usize = 1500;
const EVERY: usize = 250;
const THRESHOLD: f64 = 1.2;

fn run(set: &Setup, whole: &State, dims: [usize; 2], balance: Option<f64>) -> Vec<Seen> {
    run_ranks(dims[0] * dims[1], |l: Local| {
        let d = Decomposed::new(l, set, Some(dims), 0.5).unwrap();
        let mut d = d.with_balance(balance);
        let mut s = d.start(set, whole);
        let start = d.imbalance();
        let first = d.owned(&s.particles);
        let (mut hashes, mut worst) = (Vec::new(), 1.0f64);
        for k in 0..STEPS {
            step_on(set, &mut s, 5e-4, &mut NoHooks, &mut d);
            worst = worst.max(d.imbalance());
            if k % EVERY == EVERY - 1 {
                hashes.push(d.state_hash(&s));
            }
        }
        Seen {
            hashes,
            start,
            worst,
            rebalances: d.rebalances(),
            owned: [first, d.owned(&s.particles)],
        }
    })
}

/// The lump thrown from the corner on 2 × 1, 4 × 1, 1 × 4 and 2 × 2 ranks, with the
/// cuts moving when the most particles on a rank pass 1.2 × the mean, and with equal
/// boxes: the serial state hash every 250 steps either way. Balanced, the ranks start
/// within the threshold and every rank owns particles at the end; with equal boxes most
/// start empty, and on 4 × 1 the corner's rank, which held most, ends empty.
#[test]
fn a_lump_thrown_across_the_box_is_balanced_and_keeps_the_serial_hash() {
    let set = corner_setup();
    let whole = State::new(&set, lump());
    let mut serial = whole.clone();
    let mut want = Vec::new();
    for k in 0..STEPS {
        step(&set, &mut serial, 5e-4);
        if k % EVERY == EVERY - 1 {
            want.push(state_hash(&serial));
        }
    }
    for dims in [[1, 1], [2, 1], [4, 1], [1, 4], [2, 2]] {
        for balance in [Some(THRESHOLD), None] {
            let out = run(&set, &whole, dims, balance);
            for (r, o) in out.iter().enumerate() {
                assert_eq!(o.hashes, want, "{dims:?}, balance {balance:?}, rank {r}");
            }
            let o = &out[0];
            let first: Vec<usize> = out.iter().map(|o| o.owned[0]).collect();
            let owned: Vec<usize> = out.iter().map(|o| o.owned[1]).collect();
            eprintln!(
                "{dims:?} balance {balance:?}: max/mean at the start {:.3}, worst after a rebuild {:.3}, {} rebalances, owned at the start {first:?}, at the end {owned:?}",
                o.start, o.worst, o.rebalances
            );
            // Every rank measures and decides the same.
            assert!(out
                .iter()
                .all(|q| (q.start, q.worst, q.rebalances) == (o.start, o.worst, o.rebalances)));
            let n = dims[0] * dims[1];
            match balance {
                _ if n == 1 => assert_eq!((o.start, o.rebalances), (1.0, 0)),
                Some(t) => {
                    assert!(o.worst <= t, "{dims:?}: {} after a rebuild", o.worst);
                    assert!(o.rebalances >= 1);
                    assert!(owned.iter().all(|&k| k > 0), "{dims:?}: {owned:?}");
                }
                None => {
                    assert!(o.start >= 1.4, "{dims:?}: {} at the start", o.start);
                    assert_eq!(o.rebalances, 0);
                }
            }
            if dims == [4, 1] && balance.is_none() {
                // The corner's box empties.
                assert!(first[0] > 200 && owned[0] == 0, "{first:?} → {owned:?}");
            }
        }
    }
}

/// A settled bed on 1 × 4 ranks with equal boxes (the top one nearly empty), then a
/// rebuild with balancing on: the cuts move once, every rank gets about a quarter of
/// the disks, and the state hash (springs by id), the contact count and every wall
/// spring are the serial ones bit for bit.
#[test]
fn a_rebalance_keeps_every_contact_and_spring() {
    let (set, p) = peer::bed(160, 20);
    let mut whole = State::new(&set, p);
    for _ in 0..2000 {
        step(&set, &mut whole, 5e-4);
    }
    let count = |s: &State, owns: &dyn Fn(usize) -> bool| {
        let (p, l) = (&s.particles, &s.contacts);
        (0..l.nbr.len())
            .filter(|&e| {
                let (i, j) = (l.owner[e] as usize, l.nbr[e] as usize);
                let d = set.domain.min_image(p.pos[j] - p.pos[i]);
                let lower = if p.id[i] < p.id[j] { i } else { j };
                d.length() < p.radius[i] + p.radius[j] && owns(lower)
            })
            .count() as u64
    };
    let contacts = count(&whole, &|_| true);
    assert!(contacts > 60, "{contacts} contacts");
    let mut want_walls: Vec<(u32, u64)> = (0..whole.particles.len())
        .map(|i| {
            (
                whole.particles.id[i],
                whole.contacts.wall_shear[i].to_bits(),
            )
        })
        .collect();
    want_walls.sort_unstable();
    assert!(want_walls.iter().filter(|w| w.1 != 0).count() > 10);
    let out = run_ranks(4, |l| {
        let mut d = Decomposed::new(l, &set, Some([1, 4]), 0.5).unwrap();
        let mut s = d.start(&set, &whole);
        let before = (d.imbalance(), d.state_hash(&s), count(&s, &|i| d.owns(i)));
        let mut d = d.with_balance(Some(1.05));
        d.migrate(&set, &mut s);
        s.contacts.rebuild(&set, &mut s.particles);
        d.rebuilt(&set, &mut s);
        let after = (d.imbalance(), d.state_hash(&s), count(&s, &|i| d.owns(i)));
        let walls: Vec<(u32, u64)> = (0..s.particles.len())
            .filter(|&i| d.owns(i))
            .map(|i| (s.particles.id[i], s.contacts.wall_shear[i].to_bits()))
            .collect();
        (before, after, d.rebalances(), d.owned(&s.particles), walls)
    });
    let hash = state_hash(&whole);
    let (before, after) = (out[0].0, out[0].1);
    eprintln!(
        "settled bed on 1 × 4: max/mean {:.3} with equal boxes, {:.3} after the rebalance; owned {:?}",
        before.0,
        after.0,
        out.iter().map(|o| o.3).collect::<Vec<_>>()
    );
    assert!(before.0 > 1.2, "{}", before.0);
    assert!(after.0 <= 1.05, "{}", after.0);
    for (r, o) in out.iter().enumerate() {
        assert_eq!((o.0 .1, o.1 .1, o.2), (hash, hash, 1), "rank {r}");
    }
    for k in 0..2 {
        let total: u64 = out.iter().map(|o| [o.0, o.1][k].2).sum();
        assert_eq!(total, contacts, "contacts {}", ["before", "after"][k]);
    }
    let mut walls: Vec<(u32, u64)> = out.iter().flat_map(|o| o.4.clone()).collect();
    walls.sort_unstable();
    assert_eq!(walls, want_walls, "wall springs after the rebalance");
}
