//! What a run spread over ranks sent, as a user reads it: per rank and per step, by
//! stage (the engine's `decomp::traffic`), for `summary.json` and `grains bench dem`.
//! The engines' own books are two types (one per build of the DEM source); this is the
//! one both are read into.

use serde_json::{json, Map, Value};

/// One stage's traffic, per rank and per step (means over the ranks).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PerStep {
    /// Point-to-point messages sent.
    pub messages: f64,
    /// Collective calls.
    pub collectives: f64,
    /// Bytes sent (a collective: this rank's words).
    pub sent: f64,
    /// Bytes received (a collective: every rank's words, as an all-gather hands back).
    pub received: f64,
}

impl PerStep {
    fn json(&self) -> Value {
        json!({
            "messages": self.messages,
            "collectives": self.collectives,
            "bytes_sent": self.sent,
            "bytes_received": self.received,
        })
    }
}

/// A run's communication over every rank.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Comm {
    /// Ranks.
    pub ranks: u64,
    /// Steps each rank took (this segment of the run).
    pub steps: u64,
    /// Rebuilds each rank took part in.
    pub rebuilds: u64,
    /// Particles owned, over every rank, at the end.
    pub owned: u64,
    /// Ghosts held, over every rank, at the end.
    pub ghosts: u64,
    /// The ghost refresh, the rebuilds (spread over the steps), the step's reductions,
    /// the energy ledger's sums (at samples and gathers), and what is outside the step
    /// (start, samples, state hash, whole-state gathers), in that order
    /// ([`Comm::STAGES`]).
    pub stages: [PerStep; 5],
    /// The most bytes one rank sent per step in the stepping (all stages but outputs).
    pub busiest_sent: f64,
    /// The most bytes one rank received per step in the stepping.
    pub busiest_received: f64,
}

impl Comm {
    /// The stages' names, as in `summary.json`.
    pub const STAGES: [&'static str; 5] = ["ghosts", "rebuild", "reductions", "ledger", "other"];

    /// Ghosts per owned particle, over every rank.
    pub fn ghost_fraction(&self) -> f64 {
        self.ghosts as f64 / self.owned.max(1) as f64
    }

    /// Bytes one rank sends per step in the stepping (every stage but outputs), mean.
    pub fn bytes_per_step(&self) -> f64 {
        self.stages[..4].iter().map(|s| s.sent).sum()
    }

    /// Bytes one rank sends at one rebuild, mean.
    pub fn bytes_per_rebuild(&self) -> f64 {
        self.stages[1].sent * self.steps as f64 / self.rebuilds.max(1) as f64
    }

    /// Into a summary's `counts`: `ghost_fraction`, `comm_bytes_per_step` and the
    /// breakdown under `comm`.
    pub fn insert_into(&self, counts: &mut Map<String, Value>) {
        counts.insert("ghost_fraction".into(), self.ghost_fraction().into());
        counts.insert("comm_bytes_per_step".into(), self.bytes_per_step().into());
        let mut per = Map::new();
        for (name, s) in Self::STAGES.iter().zip(&self.stages) {
            per.insert((*name).into(), s.json());
        }
        counts.insert(
            "comm".into(),
            json!({
                "ranks": self.ranks,
                "steps": self.steps,
                "rebuilds": self.rebuilds,
                "owned": self.owned,
                "ghosts": self.ghosts,
                "per_rank_and_step": per,
                "bytes_per_rebuild": self.bytes_per_rebuild(),
                "busiest_rank_bytes_sent_per_step": self.busiest_sent,
                "busiest_rank_bytes_received_per_step": self.busiest_received,
            }),
        );
    }

    /// As `key: value` lines (`grains bench dem` on ranks).
    pub fn lines(&self) -> Vec<(String, String)> {
        let mut l = vec![
            (
                "ghost fraction".to_string(),
                format!("{:.4} ghosts per owned particle", self.ghost_fraction()),
            ),
            (
                "comm bytes per step".to_string(),
                format!(
                    "{:.0} sent per rank (mean; busiest rank {:.0} sent, {:.0} received)",
                    self.bytes_per_step(),
                    self.busiest_sent,
                    self.busiest_received
                ),
            ),
        ];
        for (name, s) in Self::STAGES.iter().zip(&self.stages).take(4) {
            l.push((
                format!("comm {name}"),
                format!(
                    "{:.1} messages, {:.2} collectives, {:.0} B sent, {:.0} B received per rank and step",
                    s.messages, s.collectives, s.sent, s.received
                ),
            ));
        }
        l.push((
            "comm per rebuild".to_string(),
            format!(
                "{:.0} B sent per rank ({} rebuilds)",
                self.bytes_per_rebuild(),
                self.rebuilds
            ),
        ));
        l
    }
}
