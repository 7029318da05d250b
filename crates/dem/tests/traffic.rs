//! The decomposition's message books (`decomp::traffic`) against what the exchange
//! must send: a step's ghost refresh is 8 words per ghost to each neighbour holding it,
//! the energy ledger sends nothing while the run steps and a fixed number of words when
//! its figures are asked for, and the totals over the ranks count every ghost once.

use grains_dem::decomp::local::run_ranks;
use grains_dem::decomp::traffic::Flow;
use grains_dem::decomp::{words, Decomposed};
use grains_dem::{step_on, LedgerSums, NoHooks, State};

#[path = "common/peer.rs"]
mod peer;

/// 600 disks springing apart on 2 × 1 and 2 × 2 ranks with the ledger on: every step
/// without a rebuild sends exactly the ghost bytes the lists promise, in one message
/// per neighbour, and nothing for the ledger, whose figures cost one sum of
/// [`LedgerSums::WORDS`] words when asked; a rebuild's traffic goes to the rebuild's
/// books.
#[test]
fn each_step_sends_what_the_ghost_lists_and_the_ledger_promise() {
    let (set, mut p) = peer::bed(600, 20);
    peer::squeeze(&mut p, 20);
    let mut whole = State::new(&set, p);
    grains_dem::ledger_sums::start(&set, &mut whole).unwrap();
    let n = whole.particles.len() as u64;
    assert_eq!(words::MOTION_WORDS, 8, "x, y, vx, vy, ω, fx, fy, τ");
    for dims in [[2, 1], [2, 2]] {
        let ranks = dims[0] * dims[1];
        let out = run_ranks(ranks, |l| {
            let mut d = Decomposed::new(l, &set, Some(dims), 0.5).unwrap();
            let mut s = d.start(&set, &whole);
            let (mut plain, mut rebuilt) = (0, 0);
            for _ in 0..300 {
                let (before, promised) = (d.traffic(), d.ghost_bytes_per_step());
                let builds = s.contacts.builds;
                step_on(&set, &mut s, 5e-4, &mut NoHooks, &mut d);
                let after = d.traffic();
                assert_eq!(after.ledger, Flow::default());
                assert_eq!(after.steps, before.steps + 1);
                let ghosts = diff(after.ghosts, before.ghosts);
                assert_eq!(ghosts.messages, d.neighbours() as u64);
                if s.contacts.builds == builds {
                    assert_eq!(ghosts.sent, promised);
                    assert_eq!(after.rebuild, before.rebuild);
                    plain += 1;
                } else {
                    assert_eq!(after.rebuilds, before.rebuilds + 1);
                    assert!(after.rebuild.sent > before.rebuild.sent);
                    rebuilt += 1;
                }
                assert_eq!(ghosts.sent, d.ghost_bytes_per_step());
            }
            let before = d.traffic();
            let own = grains_dem::ledger_sums::sums(&s, |i| d.owns(i)).unwrap();
            let l = own.total(&d).figures();
            assert!(l.damping > 0.0);
            let bytes = 8 * LedgerSums::WORDS as u64;
            let ledger = Flow {
                messages: 0,
                collectives: 1,
                sent: bytes,
                received: bytes * ranks as u64,
            };
            assert_eq!(diff(d.traffic().ledger, before.ledger), ledger);
            let t = d.traffic_over_ranks(&s);
            let held = s.particles.len() as u64;
            (plain, rebuilt, t, held)
        });
        let (plain, rebuilt, t, _) = out[0];
        assert!(
            plain > 100 && rebuilt > 2,
            "{plain} plain steps, {rebuilt} rebuilds"
        );
        // Every ghost received was sent: the totals balance, and count every ghost.
        assert_eq!(t.sum.ghosts.sent, t.sum.ghosts.received, "{dims:?}");
        // (A rebuild's books also hold the balance counts, an all-gather: not even.)
        assert!(t.sum.rebuild.messages >= 2 * t.sum.rebuilds, "{dims:?}");
        assert_eq!((t.ranks, t.owned, t.steps()), (ranks as u64, n, 300));
        let held: u64 = out.iter().map(|o| o.3).sum();
        assert_eq!(t.ghosts, held - n, "{dims:?}");
        assert!(t.most_sent >= t.sum.stepping().sent / ranks as u64);
        assert_eq!(out.iter().map(|o| o.2).collect::<Vec<_>>(), vec![t; ranks]);
    }
}

fn diff(a: Flow, b: Flow) -> Flow {
    Flow {
        messages: a.messages - b.messages,
        collectives: a.collectives - b.collectives,
        sent: a.sent - b.sent,
        received: a.received - b.received,
    }
}
