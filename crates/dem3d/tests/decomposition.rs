//! The domain decomposition of the 3D engine on in-process ranks (threads joined by
//! channels): the code path an MPI run takes, with nothing but cargo. The 2D tests
//! (`crates/dem/tests/decomposition.rs`) hold their 2 × 2 twins.

use glam::DVec3;
use grains_dem3d::decomp::local::{run_ranks, Local};

#[path = "../../dem/tests/common/grids.rs"]
mod grids;

use grains_dem3d::decomp::{Decomposed, RankGrid};
use grains_dem3d::diagnostics::{measure, state_hash};
use grains_dem3d::granular::{Damping, GranularParams, Normal, Rolling, Tangential};
use grains_dem3d::{
    step, step_on, ContactModel, Domain, Exchange, Material, NoHooks, PairTable, Particles, Setup,
    State, Wall, WallShape,
};
use grids::on_grids;

/// Density 1, spheres (I = 2/5 m r²).
fn material() -> Material {
    Material {
        name: "m".into(),
        density: 1.0,
        youngs: None,
        poisson: None,
        restitution: None,
        friction: None,
        inertia_factor: 0.4,
    }
}

/// The linear law with history: k_t = 2/7 k_n, γ_t = γ_n / 2, μ = 0.3.
fn hooke() -> ContactModel {
    ContactModel::hooke_history(4000.0, 87.0, 0.3)
}

/// Hertz–Mindlin with Tsuji damping, `sds` rolling and `marshall` twisting resistance.
fn hertz_mindlin() -> GranularParams {
    let mut law = GranularParams::lammps(
        Normal::HertzMaterial,
        1e5,
        Damping::Tsuji,
        0.5,
        0.3,
        Tangential::Mindlin,
        None,
        1.0,
        0.3,
    );
    law.rolling = Some(Rolling {
        kr: 500.0,
        gamma_r: 5.0,
        mu_r: 0.1,
    });
    law.twisting = true;
    law
}

/// The floor z = 0.
fn floor() -> Wall {
    Wall::fixed(
        "floor",
        WallShape::Plane {
            point: [0.0, 0.0, 0.0],
            normal: [0.0, 0.0, 1.0],
        },
        None,
    )
}

/// `layers` layers of `nx` × `nx` spheres (diameters 0.88..0.98) `spacing` apart, in a
/// box periodic along x and y on a floor, under unit gravity; a little sideways motion.
fn bed(nx: usize, layers: usize, spacing: f64) -> (Setup, Particles) {
    let domain = Domain {
        lo: DVec3::ZERO,
        hi: DVec3::new(nx as f64, nx as f64, layers as f64 + 2.0),
        periodic: [true, true, false],
    };
    let setup = Setup::new(
        domain,
        vec![material()],
        hooke(),
        vec![floor()],
        DVec3::new(0.0, 0.0, -1.0),
        0.1,
    )
    .unwrap();
    let mut p = Particles::default();
    let mut x: u64 = 12345;
    for k in 0..nx * nx * layers {
        x = x
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let d = 0.88 + 0.1 * ((x >> 11) as f64 / (1u64 << 53) as f64);
        let (i, j, l) = (k % nx, (k / nx) % nx, k / (nx * nx));
        let at = spacing * DVec3::new(i as f64 + 0.5, j as f64 + 0.5, l as f64) + 0.5 * DVec3::Z;
        let v = DVec3::new(
            0.01 * ((k % 7) as f64 - 3.0),
            0.01 * ((k % 5) as f64 - 2.0),
            0.0,
        );
        p.push(at, 0.5 * d, 1.0, 0.4, 0, v, DVec3::ZERO);
    }
    (setup, p)
}

/// Touching pairs listed in `s` (the min-image distance under the sum of radii); with
/// `d`, only those whose lower id the rank owns (each pair once over the ranks).
fn touching(set: &Setup, s: &State, d: Option<&Decomposed<Local>>) -> u64 {
    let (p, l) = (&s.particles, &s.contacts);
    let mut n = 0;
    for e in 0..l.nbr.len() {
        let (i, j) = (l.owner[e] as usize, l.nbr[e] as usize);
        let r = p.radius[i] + p.radius[j];
        let lower = if p.id[i] < p.id[j] { i } else { j };
        let counted = d.is_none_or(|d| d.owns(lower));
        if set.domain.min_image(p.pos[j] - p.pos[i]).length() < r && counted {
            n += 1;
        }
    }
    n
}

/// Directions that cross a face (one axis), an edge (two) and a corner (three) of the
/// 2 × 2 × 2 grid, both ways, and one oblique.
const DIRECTIONS: [[f64; 3]; 9] = [
    [1.0, 0.0, 0.0],
    [0.0, -1.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 1.0, 0.0],
    [0.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, 1.0, 1.0],
    [1.0, 0.37, -0.61],
];

/// One free sphere on a 2 × 2 × 2 grid of a unit box, periodic and not: for each
/// direction it crosses faces, edges and the corner where the eight boxes meet, is
/// always owned by exactly one rank (within skin/2 of its box), and follows x0 + v t to
/// 1e-12, bit for bit the serial path. Along the main diagonal it goes from rank 0
/// straight to rank 7.
#[test]
fn a_sphere_crosses_every_face_edge_and_corner_of_a_2x2x2_grid() {
    for periodic in [true, false] {
        let domain = Domain {
            lo: DVec3::ZERO,
            hi: DVec3::ONE,
            periodic: [periodic; 3],
        };
        let set = Setup::new(
            domain,
            vec![material()],
            hooke(),
            vec![],
            DVec3::ZERO,
            0.004,
        )
        .unwrap();
        let grid = RankGrid::new(domain, [2, 2, 2], 8, 0.024).unwrap();
        let dt = 1e-3;
        // A closed box: from its centre region to within 0.2 of the faces.
        let steps = if periodic { 1500 } else { 400 };
        let mut visited = [false; 8];
        for dir in DIRECTIONS {
            let v = DVec3::from_array(dir);
            // Closed: start on the side the sphere leaves, so it crosses the middle.
            let x0 = if periodic {
                DVec3::splat(0.3)
            } else {
                let side = |c: f64| {
                    if c == 0.0 {
                        0.3
                    } else {
                        0.5 - 0.25 * c.signum()
                    }
                };
                DVec3::from_array(dir.map(side))
            };
            let mut p = Particles::default();
            p.push(x0, 0.01, 1.0, 0.4, 0, v, DVec3::ZERO);
            let whole = State::new(&set, p);
            let mut serial = whole.clone();
            let mut path = Vec::new();
            for _ in 0..steps {
                step(&set, &mut serial, dt);
                path.push(serial.particles.pos[0]);
            }
            let per_rank = run_ranks(8, |l| {
                let mut d = Decomposed::new(l, &set, Some([2, 2, 2]), 0.01).unwrap();
                let mut s = d.start(&set, &whole);
                let mut mine = Vec::new();
                for _ in 0..steps {
                    step_on(&set, &mut s, dt, &mut NoHooks, &mut d);
                    let at = (0..s.particles.len()).find(|&i| d.owns(i));
                    mine.push(at.map(|i| (s.particles.pos[i], s.particles.vel[i])));
                }
                mine
            });
            let owner =
                |k: usize| -> Vec<usize> { (0..8).filter(|&r| per_rank[r][k].is_some()).collect() };
            for k in 0..steps {
                let owners = owner(k);
                assert_eq!(owners.len(), 1, "{v}, step {k}: owned by {owners:?}");
                let (x, vel) = per_rank[owners[0]][k].unwrap();
                assert!(grid.distance(x, owners[0]) <= 0.002, "step {k}: {x}");
                visited[owners[0]] = true;
                assert_eq!(x, path[k], "{v}, step {k}: the serial path");
                assert_eq!(vel, v);
                let want = x0 + v * ((k + 1) as f64 * dt);
                let off = if periodic {
                    let o = x - (want - want.floor());
                    o - o.round()
                } else {
                    x - want
                };
                assert!(off.length() < 1e-12, "{v}, step {k}: {x} against {want}");
            }
            if dir == [1.0, 1.0, 1.0] {
                let corner = (1..steps).any(|k| owner(k - 1) == [0] && owner(k) == [7]);
                assert!(corner, "periodic {periodic}: not through the corner");
            }
        }
        assert!(visited.iter().all(|&b| b), "visited {visited:?}");
    }
}

/// A settled bed of 256 spheres on 2 × 2 × 2 ranks (the cut at mid-height runs through
/// it) keeps every contact and spring; moved by half the box along both periodic axes,
/// every sphere changes rank with its springs and wall springs, and the state hash
/// (springs by id), the contact count, every wall spring and the figures are the
/// serial ones bit for bit.
#[test]
fn a_settled_3d_bed_keeps_its_contacts_and_springs_through_migration() {
    let nx = 8;
    let (set, p) = bed(nx, 4, 0.92);
    let mut whole = State::new(&set, p);
    for _ in 0..8000 {
        step(&set, &mut whole, 5e-4);
    }
    let half = 0.5 * nx as f64;
    let shift = |s: &mut State| {
        for x in s.particles.pos.iter_mut() {
            *x = set.domain.wrap(*x + DVec3::new(half, half, 0.0));
        }
    };
    let mut moved = whole.clone();
    shift(&mut moved);
    moved.contacts.rebuild(&set, &mut moved.particles);
    let want = [
        (state_hash(&whole), touching(&set, &whole, None)),
        (state_hash(&moved), touching(&set, &moved, None)),
    ];
    assert!(want[0].1 > 250, "{} contacts", want[0].1);
    let bits = |t: DVec3| t.to_array().map(f64::to_bits);
    let springs = whole.contacts.shear.iter().filter(|x| **x != DVec3::ZERO);
    assert!(springs.count() > 200);
    let walls_wound = whole
        .contacts
        .wall_shear
        .iter()
        .filter(|x| **x != DVec3::ZERO);
    assert!(walls_wound.count() > 20);
    let out = run_ranks(8, |l| {
        let mut d = Decomposed::new(l, &set, Some([2, 2, 2]), 0.5).unwrap();
        let mut s = d.start(&set, &whole);
        let before = (d.state_hash(&s), touching(&set, &s, Some(&d)));
        let figures = d.measure(&set, &s);
        let across = (0..s.contacts.nbr.len())
            .filter(|&e| d.owns(s.contacts.owner[e] as usize) != d.owns(s.contacts.nbr[e] as usize))
            .count();
        shift(&mut s);
        Exchange::migrate(&mut d, &set, &mut s);
        s.contacts.rebuild(&set, &mut s.particles);
        Exchange::rebuilt(&mut d, &set, &mut s);
        let walls: Vec<(u32, [u64; 3])> = (0..s.particles.len())
            .filter(|&i| d.owns(i))
            .map(|i| (s.particles.id[i], bits(s.contacts.wall_shear[i])))
            .collect();
        let after = (d.state_hash(&s), touching(&set, &s, Some(&d)));
        ([before, after], walls, figures, across)
    });
    let serial = measure(&set, &whole);
    for (r, o) in out.iter().enumerate() {
        assert_eq!(o.0[0].0, want[0].0, "rank {r}: hash before the move");
        assert_eq!(o.0[1].0, want[1].0, "rank {r}: hash after the move");
        assert_eq!(o.2, serial, "rank {r}: figures");
        assert!(o.3 > 0, "rank {r}: no pair across its boundary");
    }
    for k in 0..2 {
        let total: u64 = out.iter().map(|o| o.0[k].1).sum();
        assert_eq!(total, want[k].1, "contacts {}", ["before", "after"][k]);
    }
    let mut walls: Vec<_> = out.iter().flat_map(|o| o.1.clone()).collect();
    walls.sort_unstable();
    let m = &moved;
    let mut want_walls: Vec<_> = (0..m.particles.len())
        .map(|i| (m.particles.id[i], bits(m.contacts.wall_shear[i])))
        .collect();
    want_walls.sort_unstable();
    assert_eq!(walls, want_walls, "wall springs after the move");
}

/// The serial run's state hash every `every` of `steps` steps of `dt` from `whole`.
fn serial_hashes(set: &Setup, whole: &State, (dt, steps, every): (f64, usize, usize)) -> Vec<u64> {
    let mut serial = whole.clone();
    let mut want = Vec::new();
    for k in 0..steps {
        step(set, &mut serial, dt);
        if k % every == every - 1 {
            want.push(state_hash(&serial));
        }
    }
    want
}

/// Checks the state hash on every rank of each grid against the serial run's.
fn hashes_on(set: &Setup, whole: &State, plan: (f64, usize, usize), grids: &[([usize; 3], usize)]) {
    let want = serial_hashes(set, whole, plan);
    on_grids(set, whole, plan, grids, &want, |d, s| d.state_hash(s));
}

/// The grids of the equality tests: 1, 2 (cut along each axis), 4 and 8 ranks.
const GRIDS: [([usize; 3], usize); 7] = [
    ([1, 1, 1], 1),
    ([2, 1, 1], 1),
    ([1, 2, 1], 2),
    ([1, 1, 2], 1),
    ([2, 2, 1], 1),
    ([2, 1, 2], 2),
    ([2, 2, 2], 1),
];

/// A squeezed bed (spacing 0.9 against diameters 0.88..0.98: each sphere overlaps up to
/// six neighbours, so a force is a sum of several pair terms whose order matters)
/// springing apart and falling onto the floor under the linear law: the serial state
/// hash every 200 steps on 1, 2, 4 and 8 ranks, at 1 and 2 threads.
#[test]
fn a_3d_bed_has_the_serial_hash_on_1_2_4_and_8_ranks_linear() {
    let (set, p) = bed(6, 5, 0.9);
    let whole = State::new(&set, p);
    hashes_on(&set, &whole, (5e-4, 600, 200), &GRIDS);
}

/// The same bed under Hertz–Mindlin with rolling and twisting resistance: spheres cross
/// the cuts with their whole pair and wall histories; the serial state hash (histories
/// included) every 200 steps on 1, 2, 4 and 8 ranks.
#[test]
fn a_3d_bed_has_the_serial_hash_on_1_2_4_and_8_ranks_hertz_mindlin() {
    let (mut set, p) = bed(6, 5, 0.9);
    set.granular = Some(PairTable::from_fn(1, |_, _| hertz_mindlin()));
    let whole = State::new(&set, p);
    let mut serial = whole.clone();
    for _ in 0..400 {
        step(&set, &mut serial, 5e-4);
    }
    let l = &serial.contacts;
    // The premise: histories with sliding, rolling and twisting springs wound up.
    let wound = (0..l.len())
        .filter_map(|e| l.granular(e))
        .filter(|h| h.iter().filter(|x| **x != 0.0).count() > 4)
        .count();
    assert!(wound > 30, "{wound} wound histories");
    hashes_on(&set, &whole, (5e-4, 600, 200), &GRIDS);
}

/// A column of spheres falling onto the floor, on a 1 × 1 × 4 grid: the top two ranks
/// never own a sphere (nor, the top one, a ghost), and every rank still has the serial
/// state hash.
#[test]
fn a_rank_that_owns_no_spheres_has_the_serial_hash() {
    let domain = Domain {
        lo: DVec3::ZERO,
        hi: DVec3::new(1.0, 1.0, 2.0),
        periodic: [false; 3],
    };
    let set = Setup::new(
        domain,
        vec![material()],
        hooke(),
        vec![floor()],
        DVec3::new(0.0, 0.0, -9.81),
        0.01,
    )
    .unwrap();
    let mut p = Particles::default();
    for k in 0..10 {
        let s = if k % 2 == 0 { 0.003 } else { -0.003 };
        let at = DVec3::new(0.5 + s, 0.5 - s, 0.1 + 0.045 * k as f64);
        p.push(at, 0.02, 1.0, 0.4, 0, DVec3::ZERO, DVec3::ZERO);
    }
    let whole = State::new(&set, p);
    let plan = (5e-5, 4000, 500);
    let want = serial_hashes(&set, &whole, plan);
    let grids = [([1, 1, 4], 1)];
    let held = on_grids(&set, &whole, plan, &grids, &want, |d, s| d.state_hash(s));
    let held = &held[0];
    // The column stays below z = 0.6: the boxes above z = 1 hold nothing.
    assert_eq!((held[2], held[3]), (0, 0));
    assert!(held[0] > 0 && held[1] > 0);
}
