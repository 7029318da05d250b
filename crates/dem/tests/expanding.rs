//! The neighbour list judged in an expanding frame (grains_dem::verlet) never misses a
//! contact, and rebuilds less often than the classic rule on a ring thrown outward.

use glam::DVec2;
use grains_dem::{step, Domain, Particles, Setup, State};

#[path = "common/peer.rs"]
#[allow(dead_code)]
mod peer;

fn ring(frame: bool, r_out: f64) -> (Setup, Particles) {
    let (material, model) = (peer::material(), peer::hooke(1.0e4, 5.0));
    let domain = Domain {
        lo: DVec2::splat(-200.0),
        hi: DVec2::splat(200.0),
        periodic: [false, false],
    };
    let mut setup = Setup::new(domain, vec![material], model, vec![], DVec2::ZERO, 0.5).unwrap();
    if frame {
        setup.expanding_from = Some(DVec2::ZERO);
    }
    let mut p = Particles::default();
    let mut x: u64 = 987654321;
    let mut next = || {
        x = x
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (x >> 11) as f64 / (1u64 << 53) as f64
    };
    // A triangular lattice of unit disks in the annulus 10–r_out, moving outward at 3
    // to 1 (faster inside, so the inner layers run into the outer ones), with noise.
    let dy = 3f64.sqrt() / 2.0;
    let k = (r_out / dy).ceil() as i32 + 1;
    for row in -k..=k {
        for col in -k..=k {
            let at = DVec2::new(col as f64 + 0.5 * (row & 1) as f64, row as f64 * dy);
            let r = at.length();
            if !(10.0..r_out).contains(&r) {
                continue;
            }
            let radius = 0.45 + 0.05 * next();
            let n = at / r;
            let speed = 3.0 - 2.0 * (r - 10.0) / (r_out - 10.0) + 0.5 * (next() - 0.5);
            let noise = DVec2::new(next() - 0.5, next() - 0.5) * 0.4;
            p.push(at, radius, 1.0, 0.5, 0, speed * n + noise, 0.0);
        }
    }
    (setup, p)
}

/// Every pair that touches is in the list.
fn complete(s: &State) -> bool {
    let p = &s.particles;
    let c = &s.contacts;
    let n = p.len();
    let mut listed = std::collections::HashSet::new();
    for i in 0..n {
        for e in c.row[i] as usize..c.row[i + 1] as usize {
            let j = c.nbr[e] as usize;
            listed.insert((i.min(j), i.max(j)));
        }
    }
    for i in 0..n {
        for j in i + 1..n {
            let d = (p.pos[j] - p.pos[i]).length();
            if d < p.radius[i] + p.radius[j] && !listed.contains(&(i, j)) {
                return false;
            }
        }
    }
    true
}

fn run(frame: bool) -> (u64, usize) {
    let (setup, p) = ring(frame, 25.0);
    let mut s = State::new(&setup, p);
    let mut moved = 0;
    for k in 0..1500 {
        let before = s.contacts.builds;
        step(&setup, &mut s, 2e-3);
        let rebuilt = s.contacts.builds > before;
        let drifted = s
            .particles
            .pos
            .iter()
            .zip(&s.contacts.pos_at_build)
            .any(|(x, b)| (*x - *b).length() > 0.25);
        if !rebuilt && drifted {
            moved += 1;
        }
        if k % 10 == 0 || (!rebuilt && drifted) {
            assert!(
                complete(&s),
                "a touching pair is missing from the list at step {k}"
            );
        }
    }
    (s.contacts.builds, moved)
}

#[test]
fn an_expanding_ring_keeps_every_contact_with_fewer_rebuilds() {
    let (classic, kept_classic) = run(false);
    let (framed, kept_framed) = run(true);
    assert_eq!(
        kept_classic, 0,
        "the classic rule keeps no list past skin/2"
    );
    assert!(kept_framed > 0, "the frame never kept a list past skin/2");
    assert!(
        (framed as f64) < 0.7 * classic as f64,
        "rebuilds: {framed} in the frame, {classic} by the classic rule"
    );
}

/// Over many chunks (13,000 disks), the frame's sums are joined in chunk order: the run
/// is bitwise the same on 1, 2 and 3 threads, frame and all.
#[test]
fn the_frame_does_not_depend_on_the_thread_count() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let (setup, p) = ring(true, 60.0);
            assert!(p.len() > 6 * grains_dem::CHUNK);
            let mut s = State::new(&setup, p);
            for _ in 0..300 {
                step(&setup, &mut s, 2e-3);
            }
            let f = s.contacts.frame.unwrap();
            (
                grains_dem::diagnostics::state_hash(&s),
                s.contacts.builds,
                [f.shift.x.to_bits(), f.shift.y.to_bits(), f.radial.to_bits()],
            )
        })
    };
    let one = run(1);
    assert!(one.1 > 1, "the list was never rebuilt");
    assert_eq!(one, run(2));
    assert_eq!(one, run(3));
}
