//! The domain decomposition on in-process ranks (threads joined by channels): the same
//! code path an MPI run takes, with nothing but cargo.

use glam::DVec2;
use grains_dem::decomp::local::{run_ranks, Local};
use grains_dem::decomp::{Decomposed, RankGrid};
use grains_dem::diagnostics::{measure, measure_on, state_hash};
use grains_dem::{step, step_on, Domain, NoHooks, Particles, Setup, State};

#[path = "common/peer.rs"]
mod peer;

#[path = "common/grids.rs"]
mod grids;

use grids::{on_grids, pool};

/// The grids of the equality tests: 1 × 1, 2 × 1, 1 × 2 and 2 × 2 ranks, at 1 and 2
/// threads each.
const GRIDS: [([usize; 2], usize); 8] = [
    ([1, 1], 1),
    ([2, 1], 1),
    ([1, 2], 1),
    ([2, 2], 1),
    ([1, 1], 2),
    ([2, 1], 2),
    ([1, 2], 2),
    ([2, 2], 2),
];

fn setup(domain: Domain, floor: bool, gravity: DVec2, skin: f64) -> Setup {
    let walls = floor.then(peer::floor).into_iter().collect();
    let (material, model) = (peer::material(), peer::hooke(4000.0, 87.0));
    Setup::new(domain, vec![material], model, walls, gravity, skin).unwrap()
}

/// Touching pairs whose lower id this rank owns (each pair counted once over the ranks).
fn contacts(d: &Decomposed<Local>, set: &Setup, s: &State) -> u64 {
    let p = &s.particles;
    let l = &s.contacts;
    let mut n = 0;
    for e in 0..l.nbr.len() {
        let (i, j) = (l.owner[e] as usize, l.nbr[e] as usize);
        let r = p.radius[i] + p.radius[j];
        let touching = set.domain.min_image(p.pos[j] - p.pos[i]).length() < r;
        if touching && d.owns(if p.id[i] < p.id[j] { i } else { j }) {
            n += 1;
        }
    }
    n
}

/// One free particle in a periodic unit box on a 2 × 2 grid: it crosses faces and the
/// corner where the four boxes meet, always owned by exactly one rank, the rank its
/// position names, and on the path x0 + v t (bit for bit the serial run's).
#[test]
fn a_particle_crosses_every_face_and_corner_of_a_2x2_grid() {
    let domain = Domain {
        lo: DVec2::ZERO,
        hi: DVec2::ONE,
        periodic: [true, true],
    };
    let set = setup(domain, false, DVec2::ZERO, 0.004);
    let dt = 1e-3;
    let steps = 1500;
    let mut visited = [false; 4];
    for v in [
        DVec2::new(1.0, 1.0),
        DVec2::new(-1.0, 1.0),
        DVec2::new(1.0, 0.37),
        DVec2::new(0.0, -1.3),
    ] {
        let x0 = DVec2::new(0.3, 0.3);
        let mut p = Particles::default();
        p.push(x0, 0.01, 1.0, 0.5, 0, v, 0.0);
        let whole = State::new(&set, p);
        let mut serial = whole.clone();
        let mut path = Vec::new();
        for _ in 0..steps {
            step(&set, &mut serial, dt);
            path.push(serial.particles.pos[0]);
        }
        let per_rank = run_ranks(4, |l| {
            let mut d = Decomposed::new(l, &set, Some([2, 2]), 0.01).unwrap();
            let mut s = d.start(&set, &whole);
            let mut mine = Vec::new();
            for _ in 0..steps {
                step_on(&set, &mut s, dt, &mut NoHooks, &mut d);
                let at = (0..s.particles.len()).find(|&i| d.owns(i));
                mine.push(at.map(|i| (s.particles.pos[i], s.particles.vel[i])));
            }
            mine
        });
        let grid = RankGrid::new(domain, [2, 2], 4, 0.024).unwrap();
        for k in 0..steps {
            let owners: Vec<usize> = (0..4).filter(|&r| per_rank[r][k].is_some()).collect();
            assert_eq!(owners.len(), 1, "step {k}: owned by {owners:?}");
            let (x, vel) = per_rank[owners[0]][k].unwrap();
            // Ownership changes at rebuilds: between them a particle strays at most
            // skin/2 from its owner's box.
            assert!(grid.distance(x, owners[0]) <= 0.002, "step {k}: {x}");
            visited[owners[0]] = true;
            assert_eq!(x, path[k], "step {k}: the serial path");
            assert_eq!(vel, v);
            let t = (k + 1) as f64 * dt;
            let want = x0 + v * t;
            let want = want - want.floor();
            let off = x - want;
            let off = off - off.round();
            assert!(off.length() < 1e-12, "step {k}: {x} against {want}");
        }
        if v == DVec2::ONE {
            // Along the diagonal it goes through the corners, from rank 0 to rank 3.
            let owner = |k: usize| (0..4).find(|&r| per_rank[r][k].is_some()).unwrap();
            assert!((1..steps).any(|k| owner(k - 1) == 0 && owner(k) == 3));
        }
    }
    assert!(visited.iter().all(|&b| b), "visited {visited:?}");
}

/// A column of disks falling onto the floor (and toppling), each touching at most two others, so every
/// force is a sum of at most two pair terms (whose order does not matter): the state
/// hash is the serial one on 1, 2, 3 and 4 ranks and grids that cut the column,
/// including one where two ranks own nothing.
#[test]
fn a_falling_column_has_the_serial_hash_on_1_to_4_ranks() {
    let domain = Domain {
        lo: DVec2::ZERO,
        hi: DVec2::new(1.0, 2.0),
        periodic: [false, false],
    };
    let set = setup(domain, true, DVec2::new(0.0, -9.81), 0.01);
    let mut p = Particles::default();
    for k in 0..12 {
        let x = 0.5 + if k % 2 == 0 { 0.003 } else { -0.003 };
        p.push(
            DVec2::new(x, 0.3 + 0.045 * k as f64),
            0.02,
            1.0,
            0.5,
            0,
            DVec2::ZERO,
            0.0,
        );
    }
    let whole = State::new(&set, p);
    let dt = 5e-5;
    let steps = 8000;
    let mut serial = whole.clone();
    let mut hashes = Vec::new();
    let mut springs = 0;
    for k in 0..steps {
        step(&set, &mut serial, dt);
        if k % 500 == 499 {
            hashes.push(state_hash(&serial));
        }
        let live = serial.contacts.shear.iter().filter(|x| **x != 0.0).count();
        springs = springs.max(live);
        // The premise: no disk touches three others.
        let l = &serial.contacts;
        let mut touching = [0; 12];
        for e in 0..l.nbr.len() {
            let (i, j) = (l.owner[e] as usize, l.nbr[e] as usize);
            let p = &serial.particles;
            if (p.pos[j] - p.pos[i]).length() < p.radius[i] + p.radius[j] {
                touching[i] += 1;
                touching[j] += 1;
            }
        }
        assert!(touching.iter().all(|&t| t <= 2), "step {k}: {touching:?}");
    }
    assert!(springs >= 3, "the column had at most {springs} springs");
    for (ranks, dims) in [
        (1, [1, 1]),
        (2, [2, 1]),
        (3, [1, 3]),
        (4, [2, 2]),
        (4, [1, 4]),
    ] {
        let out = run_ranks(ranks, |l| {
            let mut d = Decomposed::new(l, &set, Some(dims), 0.02).unwrap();
            let mut s = d.start(&set, &whole);
            let mut hs = Vec::new();
            let mut owned = 0;
            for k in 0..steps {
                step_on(&set, &mut s, dt, &mut NoHooks, &mut d);
                if k % 500 == 499 {
                    hs.push(d.state_hash(&s));
                }
                owned = owned.max(s.particles.len());
            }
            (hs, owned)
        });
        for (r, (hs, _)) in out.iter().enumerate() {
            assert_eq!(hs, &hashes, "{dims:?}, rank {r}");
        }
        if dims == [1, 4] {
            // The column stays below y = 0.8: the top two ranks never hold a particle.
            assert_eq!((out[2].1, out[3].1), (0, 0));
            assert!(out[0].1 > 0 && out[1].1 > 0);
        }
    }
}

/// A settled bed spread over 2 × 2 ranks keeps every spring; moved by half its width
/// along the periodic axis, its particles change rank with their springs and wall
/// springs, and the contacts and springs are still the serial ones bit for bit.
#[test]
fn a_settled_bed_keeps_its_contacts_and_springs_through_migration() {
    let nx = 20;
    let (set, p) = peer::bed(8 * nx, nx);
    let mut whole = State::new(&set, p);
    for _ in 0..2000 {
        step(&set, &mut whole, 5e-4);
    }
    let shift = |s: &mut State| {
        for x in s.particles.pos.iter_mut() {
            *x = set.domain.wrap(*x + DVec2::new(0.5 * nx as f64, 0.0));
        }
    };
    let mut moved = whole.clone();
    shift(&mut moved);
    moved.contacts.rebuild(&set, &mut moved.particles);
    let count = |s: &State| {
        let p = &s.particles;
        let l = &s.contacts;
        (0..l.nbr.len())
            .filter(|&e| {
                let (i, j) = (l.owner[e] as usize, l.nbr[e] as usize);
                let d = set.domain.min_image(p.pos[j] - p.pos[i]);
                d.length() < p.radius[i] + p.radius[j]
            })
            .count() as u64
    };
    let want = [
        (state_hash(&whole), count(&whole)),
        (state_hash(&moved), count(&moved)),
    ];
    assert!(want[0].1 > 60, "{} contacts", want[0].1);
    let wall_springs = whole
        .contacts
        .wall_shear
        .iter()
        .filter(|x| **x != 0.0)
        .count();
    assert!(wall_springs > 10, "{wall_springs} wall springs");
    let out = run_ranks(4, |l| {
        let mut d = Decomposed::new(l, &set, Some([2, 2]), 0.5).unwrap();
        let mut s = d.start(&set, &whole);
        let before = (d.state_hash(&s), contacts(&d, &set, &s));
        let figures = (d.measure(&set, &s), measure_on(&set, &s, &d));
        // Every particle, ghosts too, moves by the same rounding as the serial one.
        shift(&mut s);
        grains_dem::Exchange::migrate(&mut d, &set, &mut s);
        s.contacts.rebuild(&set, &mut s.particles);
        grains_dem::Exchange::rebuilt(&mut d, &set, &mut s);
        let walls: Vec<(u32, u64)> = (0..s.particles.len())
            .filter(|&i| d.owns(i))
            .map(|i| (s.particles.id[i], s.contacts.wall_shear[i].to_bits()))
            .collect();
        (
            [before, (d.state_hash(&s), contacts(&d, &set, &s))],
            walls,
            figures,
        )
    });
    // The figures over the ranks: each particle and pair once, added in id order, so
    // the serial figures bit for bit. Counting every stored particle, ghosts included,
    // overstates them.
    let serial = measure(&set, &whole);
    assert!(serial.kinetic() > 0.0 && serial.elastic > 0.0);
    for (r, o) in out.iter().enumerate() {
        let (m, with_ghosts) = &o.2;
        assert_eq!(m, &serial, "rank {r}");
        assert!(with_ghosts.kinetic() > 1.01 * serial.kinetic());
        assert!(with_ghosts.pair_contacts > serial.pair_contacts);
    }
    let mut walls: Vec<(u32, u64)> = out.iter().flat_map(|o| o.1.clone()).collect();
    walls.sort_unstable();
    let mut want_walls: Vec<(u32, u64)> = (0..moved.particles.len())
        .map(|i| {
            (
                moved.particles.id[i],
                moved.contacts.wall_shear[i].to_bits(),
            )
        })
        .collect();
    want_walls.sort_unstable();
    assert_eq!(walls, want_walls, "wall springs after the move");
    let out: Vec<_> = out.into_iter().map(|o| o.0).collect();
    for (r, got) in out.iter().enumerate() {
        assert_eq!(got[0].0, want[0].0, "rank {r}: hash before the move");
        assert_eq!(got[1].0, want[1].0, "rank {r}: hash after the move");
    }
    for k in 0..2 {
        let total: u64 = out.iter().map(|g| g[k].1).sum();
        assert_eq!(total, want[k].1, "contacts {}", ["before", "after"][k]);
    }
}

/// A bed of 2,000 disks set on a squeezed triangular lattice (most overlap several
/// neighbours, so a force is a sum of up to six terms, whose order matters) that
/// springs apart and falls onto the floor, on 1, 2 (2 × 1 and 1 × 2) and 4 (2 × 2) ranks
/// at 1 and 2 threads each: the state hash and the floor's load are the serial ones
/// every 250 steps. Disks cross the cuts, so they migrate with their springs.
#[test]
fn a_dense_bed_has_the_serial_hash_on_1_2_and_4_ranks_and_threads() {
    let (set, mut p) = peer::bed(2000, 40);
    peer::squeeze(&mut p, 40);
    let whole = State::new(&set, p);
    let (dt, steps, every) = (5e-4, 1500, 250);
    let mut serial = whole.clone();
    let mut hashes = Vec::new();
    let mut most = 0;
    for k in 0..steps {
        step(&set, &mut serial, dt);
        if k % every == every - 1 {
            hashes.push((state_hash(&serial), serial.wall_loads.clone()));
            let (p, l) = (&serial.particles, &serial.contacts);
            let mut touching = vec![0; p.len()];
            for e in 0..l.nbr.len() {
                let (i, j) = (l.owner[e] as usize, l.nbr[e] as usize);
                let d = set.domain.min_image(p.pos[j] - p.pos[i]);
                if d.length() < p.radius[i] + p.radius[j] {
                    touching[i] += 1;
                    touching[j] += 1;
                }
            }
            most = most.max(*touching.iter().max().unwrap());
        }
    }
    // The premise: sums of three or more pair forces.
    assert!(most >= 4, "at most {most} contacts per disk");
    let on_two = pool(2).install(|| {
        let mut s = whole.clone();
        let mut hs = Vec::new();
        for k in 0..steps {
            step(&set, &mut s, dt);
            if k % every == every - 1 {
                hs.push((state_hash(&s), s.wall_loads.clone()));
            }
        }
        hs
    });
    assert_eq!(on_two, hashes, "serial, 2 threads");
    // The floor's load too: its terms are added exactly (docs/parallel.md, rule 2).
    let floor = hashes.last().unwrap().1[0].contacts;
    assert!(floor > 10, "{floor} disks on the floor");
    on_grids(&set, &whole, (dt, steps, every), &GRIDS, &hashes, |d, s| {
        (d.state_hash(s), s.wall_loads.clone())
    });
}

/// The squeezed bed of the test above under the granular law with rolling and twisting
/// resistance (the sliding and rolling springs of each history in use): disks cross the cuts with
/// their whole histories and wall histories, and the state hash (histories included,
/// keyed by ids) is the serial one every 250 steps on 1 × 1, 2 × 1, 1 × 2 and 2 × 2 ranks
/// at 1 and 2 threads.
#[test]
fn a_granular_bed_carries_its_histories_across_ranks_bit_for_bit() {
    use grains_dem::granular::{Damping, GranularParams, Normal, Rolling, Tangential};
    use grains_dem::PairTable;
    let (mut set, mut p) = peer::bed(600, 20);
    let mut law = GranularParams::lammps(
        Normal::Hooke,
        4000.0,
        Damping::Tsuji,
        0.5,
        0.3,
        Tangential::LinearHistory,
        Some(1143.0),
        0.5,
        0.3,
    );
    law.rolling = Some(Rolling {
        kr: 500.0,
        gamma_r: 5.0,
        mu_r: 0.1,
    });
    law.twisting = true;
    set.granular = Some(PairTable::from_fn(1, |_, _| law));
    peer::squeeze(&mut p, 20);
    let whole = State::new(&set, p);
    let (dt, steps, every) = (5e-4, 1000, 250);
    let mut serial = whole.clone();
    let mut hashes = Vec::new();
    let (mut rolling, mut walls) = (0, 0);
    for k in 0..steps {
        step(&set, &mut serial, dt);
        if k % every == every - 1 {
            hashes.push(state_hash(&serial));
            let l = &serial.contacts;
            let live = (0..l.len()).filter_map(|e| l.granular(e));
            // The premise: histories with their sliding and rolling springs wound up
            // (2D: [ξ_t, a_prev, ξ_roll, ξ_twist]; a disk does not twist), walls' too.
            let wound = |h: &[f64; 4]| h[0] != 0.0 && h[2] != 0.0;
            rolling = rolling.max(live.filter(wound).count());
            let wall_live = (0..l.wall_history.len())
                .filter(|&k| l.wall_history.get(k)[0] != 0.0)
                .count();
            walls = walls.max(wall_live);
        }
    }
    assert!(
        rolling > 50,
        "{rolling} histories with sliding and rolling springs"
    );
    assert!(walls > 5, "{walls} wall histories");
    on_grids(&set, &whole, (dt, steps, every), &GRIDS, &hashes, |d, s| {
        d.state_hash(s)
    });
}

/// The energy ledger of a squeezed bed springing apart: each pair's terms are counted by
/// the rank that owns its lower id into exact sums combined over the ranks, so on
/// 1 × 1, 2 × 1, 1 × 2 and 2 × 2 ranks at 1 and 2 threads the ledger is the serial one
/// bit for bit (with the state hash) every 250 steps.
#[test]
fn the_energy_ledger_is_the_serial_one_on_any_grid() {
    let (set, mut p) = peer::bed(600, 20);
    peer::squeeze(&mut p, 20);
    let mut whole = State::new(&set, p);
    grains_dem::ledger_sums::start(&set, &mut whole).expect("the ledger is kept");
    let (dt, steps, every) = (5e-4, 1000, 250);
    let mut serial = whole.clone();
    let mut want = Vec::new();
    for k in 0..steps {
        step(&set, &mut serial, dt);
        if k % every == every - 1 {
            want.push((
                state_hash(&serial),
                grains_dem::ledger_sums::figures(&serial).unwrap(),
            ));
        }
    }
    let last = want.last().unwrap().1;
    assert!(last.damping > 0.0 && last.friction > 0.0 && last.springs_released > 0.0);
    on_grids(&set, &whole, (dt, steps, every), &GRIDS, &want, |d, s| {
        let own = grains_dem::ledger_sums::sums(s, |i| d.owns(i)).unwrap();
        (d.state_hash(s), own.total(d).figures())
    });
}
