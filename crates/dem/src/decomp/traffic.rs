//! What a rank's messages cost: messages and bytes by stage of the step, counted in
//! the transport a decomposition speaks through ([`Counted`]), so that a run on a few
//! ranks says what it would send over a network on many (docs/parallel.md, "Past this
//! machine"). Counting wraps the transport rather than each call site, so nothing the
//! decomposition sends escapes the books.
//!
//! A reduction here is an all-gather (every rank receives every rank's words: the
//! order of the combination is then fixed), so a collective's `received` is its words
//! times the rank count, and a gather's is the gathered length.

use crate::comm::{Post, Reduce};
use std::cell::Cell;

/// Where in a run a message is sent.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// The step outside the exchange: the rebuild test, the wall loads.
    Step,
    /// The ghost refresh at the end of every step.
    Ghosts,
    /// A rebuild: the balance counts, migration and the fresh ghosts.
    Rebuild,
    /// Outside the step: the start, samples, the state hash, whole-state gathers.
    Other,
}

/// Messages and bytes of one kind, sent and received by one rank (or summed over
/// ranks).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Flow {
    /// Point-to-point messages sent.
    pub messages: u64,
    /// Collective calls (reductions and gathers).
    pub collectives: u64,
    /// Bytes sent (a collective: the words this rank puts in).
    pub sent: u64,
    /// Bytes received (a collective: what it hands back).
    pub received: u64,
}

impl Flow {
    const WORDS: usize = 4;

    fn words(&self) -> [u64; Self::WORDS] {
        [self.messages, self.collectives, self.sent, self.received]
    }

    fn from_words(w: &[u64]) -> Flow {
        Flow {
            messages: w[0],
            collectives: w[1],
            sent: w[2],
            received: w[3],
        }
    }

    fn add(&mut self, o: &Flow) {
        self.messages += o.messages;
        self.collectives += o.collectives;
        self.sent += o.sent;
        self.received += o.received;
    }
}

/// One rank's communication so far, by stage.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Traffic {
    /// Ghost refreshes, one per step.
    pub steps: u64,
    /// Rebuilds that went through the exchange (migration).
    pub rebuilds: u64,
    /// The per-step ghost refresh: position, velocity, spin, force and torque of each
    /// ghost, to the neighbours that hold it.
    pub ghosts: Flow,
    /// At rebuilds: the balance counts, the particles that change rank with their
    /// histories, and the fresh ghosts with every field.
    pub rebuild: Flow,
    /// The step's reductions: the rebuild test (any, max, the residuals' gather, the
    /// frame's sums, the particle count), the wall loads' exact sums; and what a run
    /// asks between steps outside its outputs (the agreement every few steps, the
    /// disk-escape test's gather at samples).
    pub reductions: Flow,
    /// The energy ledger's sums combined over the ranks: a fixed
    /// [`crate::LedgerSums::WORDS`] words each time a sample, a gather or a checkpoint
    /// asks for its figures, whatever the particle count; nothing per step.
    pub ledger: Flow,
    /// Outside the step: the start, the samples' figures, the state hash, whole-state
    /// gathers.
    pub other: Flow,
}

impl Traffic {
    const WORDS: usize = 2 + 5 * Flow::WORDS;

    /// Its numbers as words, in a fixed order (summed over ranks as integers).
    pub fn words(&self) -> Vec<u64> {
        let mut w = vec![self.steps, self.rebuilds];
        for f in self.flows() {
            w.extend(f.words());
        }
        w
    }

    /// What [`Traffic::words`] wrote.
    pub fn from_words(w: &[u64]) -> Traffic {
        assert_eq!(w.len(), Self::WORDS, "traffic words");
        let f = |k: usize| Flow::from_words(&w[2 + k * Flow::WORDS..]);
        Traffic {
            steps: w[0],
            rebuilds: w[1],
            ghosts: f(0),
            rebuild: f(1),
            reductions: f(2),
            ledger: f(3),
            other: f(4),
        }
    }

    fn flows(&self) -> [&Flow; 5] {
        [
            &self.ghosts,
            &self.rebuild,
            &self.reductions,
            &self.ledger,
            &self.other,
        ]
    }

    /// The flows of the stepping itself (ghosts, rebuilds, reductions, ledger) added
    /// together: what a run's steps cost, outputs aside.
    pub fn stepping(&self) -> Flow {
        let mut t = Flow::default();
        for f in &self.flows()[..4] {
            t.add(f);
        }
        t
    }
}

/// Every rank's traffic together ([`crate::decomp::Decomposed::traffic_over_ranks`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Totals {
    /// Ranks.
    pub ranks: u64,
    /// Every rank's [`Traffic`] summed (steps and rebuilds too: divide by `ranks`).
    pub sum: Traffic,
    /// Particles owned, over every rank.
    pub owned: u64,
    /// Ghosts held, over every rank.
    pub ghosts: u64,
    /// The most bytes one rank sent in the steps ([`Traffic::stepping`]).
    pub most_sent: u64,
    /// The most bytes one rank received in the steps.
    pub most_received: u64,
}

impl Totals {
    /// Ghosts per owned particle.
    pub fn ghost_fraction(&self) -> f64 {
        self.ghosts as f64 / self.owned.max(1) as f64
    }

    /// Steps each rank took.
    pub fn steps(&self) -> u64 {
        self.sum.steps / self.ranks.max(1)
    }

    /// `bytes` summed over the ranks, per rank and per step.
    pub fn per_rank_step(&self, bytes: u64) -> f64 {
        bytes as f64 / (self.ranks.max(1) * self.steps().max(1)) as f64
    }
}

/// A transport whose every message and collective is counted, under the stage the
/// decomposition set last.
pub struct Counted<C> {
    inner: C,
    stage: Cell<Stage>,
    traffic: Cell<Traffic>,
}

impl<C> Counted<C> {
    /// `inner`, counted from now on, at [`Stage::Other`].
    pub fn new(inner: C) -> Self {
        Counted {
            inner,
            stage: Cell::new(Stage::Other),
            traffic: Cell::new(Traffic::default()),
        }
    }

    /// The transport, back.
    pub fn into_inner(self) -> C {
        self.inner
    }

    /// What has been counted so far.
    pub fn traffic(&self) -> Traffic {
        self.traffic.get()
    }

    /// Counts what follows under `stage`; returns the stage it replaces.
    pub fn enter(&self, stage: Stage) -> Stage {
        self.stage.replace(stage)
    }

    /// Counts one step (`rebuild`: one rebuild).
    pub fn tick(&self, rebuild: bool) {
        let mut t = self.traffic.get();
        match rebuild {
            true => t.rebuilds += 1,
            false => t.steps += 1,
        }
        self.traffic.set(t);
    }

    /// Adds `f` to the flow of the current stage (`ledger`: the ledger's, whatever the
    /// stage).
    fn book(&self, ledger: bool, f: Flow) {
        let mut t = self.traffic.get();
        let flow = match self.stage.get() {
            _ if ledger => &mut t.ledger,
            Stage::Step => &mut t.reductions,
            Stage::Ghosts => &mut t.ghosts,
            Stage::Rebuild => &mut t.rebuild,
            Stage::Other => &mut t.other,
        };
        flow.add(&f);
        self.traffic.set(t);
    }
}

impl<C: Reduce> Counted<C> {
    /// Books one collective of `words` words from this rank, `got` words back.
    fn collective(&self, ledger: bool, words: usize, got: usize) {
        self.book(
            ledger,
            Flow {
                collectives: 1,
                sent: 8 * words as u64,
                received: 8 * got as u64,
                ..Flow::default()
            },
        );
    }
}

impl<C: Reduce> Reduce for Counted<C> {
    fn ranks(&self) -> usize {
        self.inner.ranks()
    }

    fn rank(&self) -> usize {
        self.inner.rank()
    }

    fn sum(&self, values: &mut [f64]) {
        self.collective(false, values.len(), values.len() * self.ranks());
        self.inner.sum(values);
    }

    fn sum_u64(&self, values: &mut [u64]) {
        self.collective(false, values.len(), values.len() * self.ranks());
        self.inner.sum_u64(values);
    }

    fn max(&self, values: &mut [f64]) {
        self.collective(false, values.len(), values.len() * self.ranks());
        self.inner.max(values);
    }

    fn gather(&self, words: Vec<u64>) -> Vec<u64> {
        let n = words.len();
        let all = self.inner.gather(words);
        self.collective(false, n, all.len());
        all
    }

    fn sum_ledger(&self, values: &mut [u64]) {
        self.collective(true, values.len(), values.len() * self.ranks());
        self.inner.sum_ledger(values);
    }
}

impl<C: Post> Post for Counted<C> {
    fn exchange(&self, outgoing: Vec<(usize, Vec<u8>)>, from: &[usize]) -> Vec<Vec<u8>> {
        let f = Flow {
            messages: outgoing.len() as u64,
            sent: outgoing.iter().map(|(_, b)| b.len() as u64).sum(),
            ..Flow::default()
        };
        let got = self.inner.exchange(outgoing, from);
        let received = got.iter().map(|b| b.len() as u64).sum();
        self.book(false, Flow { received, ..f });
        got
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decomp::local::run_ranks;

    #[test]
    fn a_known_exchange_is_counted_to_the_byte() {
        let t = run_ranks(3, |l| {
            let c = Counted::new(l);
            let r = c.rank();
            c.enter(Stage::Ghosts);
            // Rank r sends r + 1 bytes to the next rank and 5 to the one after.
            let (next, prev) = ((r + 1) % 3, (r + 2) % 3);
            c.exchange(
                vec![(next, vec![0; r + 1]), (prev, vec![0; 5])],
                &[prev, next],
            );
            c.enter(Stage::Step);
            c.sum(&mut [0.0; 4]);
            c.any(true);
            c.gather(vec![0; r]);
            c.enter(Stage::Rebuild);
            c.sum_ledger(&mut [0; 5]);
            c.max(&mut [0.0]);
            c.tick(false);
            c.traffic()
        });
        for (r, t) in t.iter().enumerate() {
            let prev = (r + 2) % 3;
            let got = (prev + 1) as u64 + 5;
            let ghosts = Flow {
                messages: 2,
                collectives: 0,
                sent: r as u64 + 1 + 5,
                received: got,
            };
            assert_eq!(t.ghosts, ghosts, "rank {r}");
            // sum of 4 words and any of 1; the gather of r words, 0 + 1 + 2 back.
            let reductions = Flow {
                messages: 0,
                collectives: 3,
                sent: 8 * (4 + 1 + r as u64),
                received: 8 * (12 + 3 + 3),
            };
            assert_eq!(t.reductions, reductions, "rank {r}");
            // Whatever the stage: 5 words each, back from 3 ranks.
            let ledger = Flow {
                messages: 0,
                collectives: 1,
                sent: 8 * 5,
                received: 8 * 3 * 5,
            };
            assert_eq!(t.ledger, ledger, "rank {r}");
            let rebuild = Flow {
                messages: 0,
                collectives: 1,
                sent: 8,
                received: 24,
            };
            assert_eq!(t.rebuild, rebuild, "rank {r}");
            assert_eq!(t.other, Flow::default());
            assert_eq!((t.steps, t.rebuilds), (1, 0));
            assert_eq!(Traffic::from_words(&t.words()), *t);
            let mut all = ghosts;
            for f in [reductions, ledger, rebuild] {
                all.add(&f);
            }
            assert_eq!(t.stepping(), all);
        }
    }
}
