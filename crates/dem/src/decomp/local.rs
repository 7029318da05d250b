//! Ranks inside one process: N threads joined by channels, one per ordered pair of
//! ranks, so the decomposition runs and is tested with nothing but cargo. The
//! reductions gather every rank's values and combine them in rank order, as
//! `grains-mpi`'s `World` does over MPI, so a run gives the same bits on either.

use crate::comm::{Post, Reduce};
use crate::decomp::words::{bytes_of, words_of};
use std::sync::mpsc::{channel, Receiver, Sender};

/// One of several in-process ranks.
pub struct Local {
    rank: usize,
    /// `to[q]` delivers to rank q.
    to: Vec<Sender<Vec<u8>>>,
    /// `from[q]` holds what rank q sent here.
    from: Vec<Receiver<Vec<u8>>>,
}

impl Local {
    /// `n` ranks wired to one another.
    pub fn world(n: usize) -> Vec<Local> {
        let mut to: Vec<Vec<Sender<Vec<u8>>>> = (0..n).map(|_| Vec::new()).collect();
        let mut from: Vec<Vec<Receiver<Vec<u8>>>> = (0..n).map(|_| Vec::new()).collect();
        for tos in to.iter_mut() {
            for froms in from.iter_mut() {
                let (tx, rx) = channel();
                tos.push(tx);
                froms.push(rx);
            }
        }
        // from[dst] was filled in source order: froms[src] is src → dst.
        to.into_iter()
            .zip(from)
            .enumerate()
            .map(|(rank, (to, from))| Local { rank, to, from })
            .collect()
    }

    fn send(&self, to: usize, bytes: Vec<u8>) {
        self.to[to]
            .send(bytes)
            .expect("every rank lives to the end");
    }

    fn recv(&self, from: usize) -> Vec<u8> {
        self.from[from].recv().expect("every rank lives to the end")
    }

    /// Every rank's words, one vector per rank, in rank order.
    fn all(&self, words: &[u64]) -> Vec<Vec<u64>> {
        for q in (0..self.ranks()).filter(|&q| q != self.rank) {
            self.send(q, bytes_of(words));
        }
        (0..self.ranks())
            .map(|q| {
                if q == self.rank {
                    words.to_vec()
                } else {
                    words_of(&self.recv(q))
                }
            })
            .collect()
    }

    fn fold(&self, values: &mut [f64], op: impl Fn(f64, f64) -> f64) {
        let mine: Vec<u64> = values.iter().map(|v| v.to_bits()).collect();
        let all = self.all(&mine);
        for (k, v) in values.iter_mut().enumerate() {
            *v = all
                .iter()
                .map(|w| f64::from_bits(w[k]))
                .reduce(&op)
                .unwrap_or(*v);
        }
    }
}

/// Runs `f` on `n` in-process ranks (one thread each) and returns each rank's answer,
/// in rank order.
pub fn run_ranks<T: Send>(n: usize, f: impl Fn(Local) -> T + Sync) -> Vec<T> {
    std::thread::scope(|s| {
        let handles: Vec<_> = Local::world(n)
            .into_iter()
            .map(|l| s.spawn(|| f(l)))
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("a rank panicked"))
            .collect()
    })
}

impl Reduce for Local {
    fn ranks(&self) -> usize {
        self.to.len()
    }

    fn rank(&self) -> usize {
        self.rank
    }

    fn sum(&self, values: &mut [f64]) {
        self.fold(values, |a, b| a + b);
    }

    fn sum_u64(&self, values: &mut [u64]) {
        let all = self.all(values);
        for (k, v) in values.iter_mut().enumerate() {
            *v = all.iter().fold(0u64, |s, w| s.wrapping_add(w[k]));
        }
    }

    fn max(&self, values: &mut [f64]) {
        // NaN wins, as a failed test must.
        self.fold(values, |a, b| if a.is_nan() || a > b { a } else { b });
    }

    fn gather(&self, words: Vec<u64>) -> Vec<u64> {
        self.all(&words).concat()
    }
}

impl Post for Local {
    fn exchange(&self, outgoing: Vec<(usize, Vec<u8>)>, from: &[usize]) -> Vec<Vec<u8>> {
        for (to, bytes) in outgoing {
            self.send(to, bytes);
        }
        from.iter().map(|&q| self.recv(q)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sums_in_rank_order_and_messages_arrive() {
        let out = run_ranks(3, |l| {
            let r = l.rank();
            let mut v = [if r == 0 { 1e16 } else { 0.0 }, 0.1 * (r + 1) as f64];
            l.sum(&mut v);
            let next = (r + 1) % 3;
            let prev = (r + 2) % 3;
            let got = l.exchange(vec![(next, vec![r as u8; r + 1])], &[prev]);
            (v, got, l.gather(vec![r as u64]))
        });
        let want = [1e16 + 0.0 + 0.0, 0.1 * 1.0 + 0.1 * 2.0 + 0.1 * 3.0];
        for (r, (v, got, all)) in out.into_iter().enumerate() {
            assert_eq!(v.map(f64::to_bits), want.map(f64::to_bits));
            let prev = (r + 2) % 3;
            assert_eq!(got, vec![vec![prev as u8; prev + 1]]);
            assert_eq!(all, vec![0, 1, 2]);
        }
    }
}
