//! The FEM–DEM ring on several ranks, on in-process ranks (the code path an `mpirun`
//! run takes, with the messages over channels instead of MPI): every rank steps the
//! whole charge and its box of the ring, and the state hash (charge and ring), the
//! history and the figures are the serial run's bit for bit.

use grains_sim::run::{self, Finished, RunOptions};
use grains_sim::Source;
use std::path::Path;

#[path = "common/on_ranks.rs"]
mod on_ranks;

use on_ranks::{
    as_pieces, columns_but, example_in, files, hashed, on_ranks, on_ranks_with, refused_everywhere,
};

/// A 2 mm PE4 charge in a ring of 0.1 mm disks (about 1,400), cut to `duration`.
fn ring(duration: f64, more: &str) -> Source {
    let text = include_str!("data/ring_tiny.toml")
        .replace("duration = 3.0e-6", &format!("duration = {duration:e}"))
        .replace(
            "snapshots = [2.0e-6]",
            &format!("snapshots = [{:e}]", 0.5 * duration),
        );
    Source {
        text: format!("{text}\n{more}"),
        origin: "t_ring.toml".into(),
        base: ".".into(),
    }
}

/// Every history column but the neighbour builds: on ranks the list is rebuilt by the
/// plain skin rule, not in the expanding frame (docs/parallel.md).
fn columns(dir: &Path) -> Vec<Vec<String>> {
    columns_but(dir, |c| c == "neighbour_builds")
}

#[test]
fn the_ring_on_1_2_and_4_ranks_is_the_serial_run() {
    let src = ring(1.0e-6, "");
    let dir = tempfile::tempdir().unwrap();
    let serial = run::run(&src, RunOptions::new(dir.path().join("serial"))).unwrap();
    assert_eq!(serial.status.name(), "completed");
    let want = serial.summary.state_hash.clone();
    for n in [1, 2, 4] {
        let out = dir.path().join(format!("ranks{n}"));
        let leader = hashed(on_ranks(&src, n, &out), &want, &format!("{n} ranks"));
        assert_eq!(leader.status, serial.status);
        let counts = &leader.summary.counts;
        assert_eq!(
            counts["ring_state_hash"],
            serial.summary.counts["ring_state_hash"]
        );
        eprintln!(
            "{n} ranks: max/mean {} at the end, {} rebalances",
            counts["rank_imbalance"], counts["rebalances"]
        );
        let (mut a, mut b) = (
            leader.summary.figures.clone(),
            serial.summary.figures.clone(),
        );
        // Counts of the candidates' detections, which follow the list's rebuilds.
        a.remove("coupling_builds");
        b.remove("coupling_builds");
        assert_eq!(a, b, "{n} ranks");
        assert_eq!(leader.summary.checks, serial.summary.checks, "{n} ranks");
        // Rank 0's files are the serial run's, each ring frame as an index and its
        // pieces (the charge's frames written once).
        assert_eq!(
            files(&out),
            as_pieces(files(&dir.path().join("serial")), n),
            "{n} ranks"
        );
        assert_eq!(
            columns(&out),
            columns(&dir.path().join("serial")),
            "{n} ranks"
        );
    }
}

/// The dispersal table of the command line's tiny-ring test (crates/cli/tests/blast.rs),
/// with maps at two chosen times and figures every 0.25 µs.
const DISPERSAL: &str = "[analysis.dispersal]\ntimes = [0.5e-6, 1.0e-6]\nevery = 0.25e-6\n\
                         [analysis.dispersal.band]\nmin_grains = 20\n";

/// The figures of a summary but the wall times and the candidates' detection count.
fn figures_but_timing(f: &Finished) -> serde_json::Map<String, serde_json::Value> {
    let mut f = f.summary.figures.clone();
    for k in ["coupling_builds", "dispersal_wall_time_s"] {
        f.remove(k);
    }
    if let Some(d) = f.get_mut("dispersal").and_then(|d| d.as_object_mut()) {
        d.remove("wall_time_s");
        d.remove("maps_wall_time_s");
    }
    f
}

/// The bytes of every file the dispersal analysis wrote under `dir`.
fn analysis_files(dir: &Path) -> Vec<(std::path::PathBuf, Vec<u8>)> {
    files(dir)
        .into_iter()
        .filter(|f| {
            let f = f.to_string_lossy();
            f.starts_with("plots/dispersal/") || f.starts_with("frames/fields")
        })
        .map(|f| {
            let bytes = std::fs::read(dir.join(&f)).unwrap();
            (f, bytes)
        })
        .collect()
}

#[test]
fn the_ring_with_its_dispersal_analysis_on_1_2_and_4_ranks_is_the_serial_run() {
    let src = ring(1.0e-6, DISPERSAL);
    let dir = tempfile::tempdir().unwrap();
    let serial = run::run(&src, RunOptions::new(dir.path().join("serial"))).unwrap();
    assert_eq!(serial.status.name(), "completed");
    let want = serial.summary.state_hash.clone();
    let analysed = serial.summary.figures["dispersal_analysed"]
        .as_u64()
        .unwrap();
    // Frames at 0, 0.5 and 1 µs, samples every 0.25 µs besides.
    assert!(analysed >= 5, "{analysed} times analysed");
    let theirs = analysis_files(&dir.path().join("serial"));
    assert!(theirs.iter().any(|(f, _)| f.ends_with("fields.pvd")));
    for n in [1, 2, 4] {
        let out = dir.path().join(format!("ranks{n}"));
        let leader = hashed(on_ranks(&src, n, &out), &want, &format!("{n} ranks"));
        assert_eq!(leader.status, serial.status);
        assert_eq!(
            figures_but_timing(&leader),
            figures_but_timing(&serial),
            "{n} ranks"
        );
        assert_eq!(leader.summary.checks, serial.summary.checks, "{n} ranks");
        assert_eq!(
            files(&out),
            as_pieces(files(&dir.path().join("serial")), n),
            "{n} ranks"
        );
        assert_eq!(columns(&out), columns(&dir.path().join("serial")));
        // The fields (.vts), their series, the maps and plots: the serial bytes.
        let ours = analysis_files(&out);
        assert_eq!(ours.len(), theirs.len(), "{n} ranks");
        for ((f, a), (_, b)) in ours.iter().zip(&theirs) {
            assert!(a == b, "{n} ranks: {} differs", f.display());
        }
    }
}

#[test]
fn the_ring_on_2_ranks_of_2_threads_is_the_serial_run() {
    let src = ring(0.5e-6, "");
    let dir = tempfile::tempdir().unwrap();
    let serial = run::run(&src, RunOptions::new(dir.path().join("serial"))).unwrap();
    let out = dir.path().join("ranks");
    let done = grains_dem::decomp::local::run_ranks(2, |l| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        pool.install(|| {
            let link = grains_sim::dem::ranks::Link(Box::new(l));
            run::run_on(&src, RunOptions::new(&out), link).map_err(|e| e.to_string())
        })
    });
    hashed(done, &serial.summary.state_hash, "2 ranks, 2 threads each");
}

#[test]
fn a_ring_checkpoint_on_4_ranks_resumes_on_2_as_the_straight_run() {
    let src = ring(1.0e-6, "");
    let dir = tempfile::tempdir().unwrap();
    let straight = run::run(&src, RunOptions::new(dir.path().join("straight"))).unwrap();
    let out = dir.path().join("split");
    let done = on_ranks_with(4, |l| {
        let mut o = RunOptions::new(&out);
        o.stop_at_step = Some(60);
        run::run_on(&src, o, l)
    });
    for (r, d) in done.iter().enumerate() {
        let d = d.as_ref().unwrap_or_else(|e| panic!("rank {r}: {e}"));
        assert_eq!(d.status.name(), "paused", "rank {r}");
    }
    let resumed = on_ranks_with(2, |l| run::resume_on(&out, RunOptions::new(&out), l));
    let leader = hashed(resumed, &straight.summary.state_hash, "resumed on 2 ranks");
    assert_eq!(leader.status, straight.status);
    assert_eq!(columns(&out), columns(&dir.path().join("straight")));
}

#[test]
fn what_ring_ranks_cannot_run_is_refused_on_every_rank() {
    let dir = tempfile::tempdir().unwrap();
    let bare = example_in("xue2019", "charge_only.toml");
    refused_everywhere(&bare, 2, &dir.path().join("a"), "a charge without [ring]");
    let bad = ring(1.0e-6, "[parallel]\nranks = [3, 1]\n");
    refused_everywhere(&bad, 2, &dir.path().join("b"), "parallel.ranks = [3, 1]");
}

/// The penalty pass of `ring`'s particles taken in the storage order `perm` (new index
/// k holds particle `perm[k]`): the charge's nodal forces, the pass's sums, and each
/// grain's force by id, as bits.
fn penalty_pass(
    sim: &grains_sim::blast::Blast,
    perm: &[u32],
) -> (
    Vec<u64>,
    Vec<u64>,
    std::collections::BTreeMap<u32, [u64; 2]>,
) {
    let ring = sim.ring.as_ref().unwrap();
    let (mut charge, mut coupling) = (sim.charge.clone(), ring.coupling.clone());
    let mut p = ring.state.particles.clone();
    p.permute(perm);
    p.force.iter_mut().for_each(|f| *f = glam::DVec2::ZERO);
    coupling.rebuild(&charge, &p);
    coupling.forces(&mut charge, &mut p);
    let nodes = charge.nodes.f_ext.iter().flat_map(|f| [f.x, f.y]);
    let sums = [
        coupling.energy,
        coupling.radial_force,
        coupling.max_penetration_ratio,
        coupling.stable_dt(),
        coupling.contacts as f64,
    ];
    let by_id = (0..p.len())
        .map(|i| (p.id[i], [p.force[i].x.to_bits(), p.force[i].y.to_bits()]))
        .collect();
    (
        nodes.map(f64::to_bits).collect(),
        sums.map(f64::to_bits).to_vec(),
        by_id,
    )
}

#[test]
fn the_penalty_pass_is_the_same_bits_in_any_storage_order() {
    use grains_sim::scenario::{self, Scenario};
    let src = ring(1.0e-6, "");
    let Scenario::FemDem(s) = scenario::parse(&src).unwrap() else {
        panic!("not fem_dem")
    };
    let a = grains_sim::blast::assemble::assemble(&s, &src.base).unwrap();
    let mut sim = grains_sim::blast::Blast::new(&s, a);
    use grains_sim::Simulation;
    // Pressed by the charge for a while, so that nodes carry several grains.
    while sim.coupling().unwrap().contacts < 100 {
        sim.advance().unwrap();
    }
    let n = sim.ring.as_ref().unwrap().state.particles.len() as u32;
    let stored: Vec<u32> = (0..n).collect();
    let reversed: Vec<u32> = (0..n).rev().collect();
    // A scramble: a stride coprime with n.
    let stride = (n / 2..n).find(|s| gcd(*s, n) == 1).unwrap();
    let scrambled: Vec<u32> = (0..n).map(|k| (k * stride) % n).collect();
    let want = penalty_pass(&sim, &stored);
    assert!(want.1[4] > 0, "no grain on the charge");
    assert_eq!(penalty_pass(&sim, &reversed), want, "reversed");
    assert_eq!(penalty_pass(&sim, &scrambled), want, "scrambled");
}

fn gcd(a: u32, b: u32) -> u32 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}
