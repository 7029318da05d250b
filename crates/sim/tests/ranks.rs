//! `grains run` on several ranks, on in-process ranks (the code path an `mpirun` run
//! takes, with the messages over channels instead of MPI): rank 0 writes the outputs,
//! the others nothing, and the summary's state hash and the history's energies are the
//! serial run's bit for bit.

use grains_core::vtk::{check_pvtp, find_array, read_appended_arrays, ReadArray};
use grains_dem::Reduce;
use grains_sim::driver::{Progress, AGREE_EVERY};
use grains_sim::run::{self, RunOptions};
use grains_sim::{Clock, Finished, Source};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

#[path = "common/on_ranks.rs"]
mod on_ranks;

use on_ranks::{
    as_pieces, columns_but, copy_dir, example_in, files, hashed, on_ranks, on_ranks_with,
    refused_everywhere,
};

fn example(name: &str) -> Source {
    example_in("dem", name)
}

/// Every column of a history, the wall loads included (added exactly on any rank
/// count: docs/parallel.md, rule 2).
fn every_column(dir: &Path) -> Vec<Vec<String>> {
    columns_but(dir, |_| false)
}

#[test]
fn a_2d_dem_run_on_2_and_4_ranks_is_the_serial_run() {
    let src = example("ranks_column.toml");
    let dir = tempfile::tempdir().unwrap();
    let serial = run::run(&src, RunOptions::new(dir.path().join("serial"))).unwrap();
    assert_eq!(serial.status.name(), "completed");
    for n in [2, 4] {
        let out = dir.path().join(format!("ranks{n}"));
        let done = on_ranks(&src, n, &out);
        for (r, d) in done.iter().enumerate() {
            let d = d.as_ref().unwrap_or_else(|e| panic!("rank {r}: {e}"));
            assert_eq!(
                d.summary.state_hash, serial.summary.state_hash,
                "{n} ranks, rank {r}"
            );
            assert_eq!(d.status, serial.status);
        }
        let leader = done[0].as_ref().unwrap();
        // Balanced by default (`[parallel] balance` = 1.2): the cuts follow the falling
        // column.
        let counts = &leader.summary.counts;
        let (imbalance, moves) = (&counts["rank_imbalance"], &counts["rebalances"]);
        eprintln!("{n} ranks: max/mean {imbalance} at the end, {moves} rebalances");
        assert!(imbalance.as_f64().unwrap() <= 1.2, "{n} ranks: {imbalance}");
        assert!(moves.as_u64().unwrap() > 0, "{n} ranks: {moves}");
        // What the ranks sent (docs/parallel.md, "Past this machine"); a serial
        // summary has none of it.
        let comm = &counts["comm"];
        assert_eq!(comm["steps"], serial.summary.steps, "{n} ranks: {comm}");
        assert_eq!(comm["owned"], 400, "{n} ranks: {comm}");
        let fraction = counts["ghost_fraction"].as_f64().unwrap();
        let ghosts = comm["ghosts"].as_f64().unwrap();
        assert_eq!(fraction, ghosts / 400.0, "{n} ranks");
        let per = &comm["per_rank_and_step"];
        let ghost_bytes = per["ghosts"]["bytes_sent"].as_f64().unwrap();
        // Each ghost's position, velocity, spin, force and torque: 8 words, at least
        // one ghost a step.
        assert!(ghost_bytes >= 64.0, "{n} ranks: {comm}");
        assert_eq!(per["ghosts"]["bytes_received"], per["ghosts"]["bytes_sent"]);
        assert_eq!(
            per["ledger"]["collectives"], 0.0,
            "2D DEM runs keep no ledger"
        );
        let stepping: f64 = ["ghosts", "rebuild", "reductions", "ledger"]
            .iter()
            .map(|k| per[k]["bytes_sent"].as_f64().unwrap())
            .sum();
        assert_eq!(counts["comm_bytes_per_step"].as_f64().unwrap(), stepping);
        for key in ["comm", "ghost_fraction", "comm_bytes_per_step"] {
            assert!(!serial.summary.counts.contains_key(key), "{key}");
        }
        assert_eq!(leader.summary.particles, serial.summary.particles);
        assert_eq!(leader.summary.frames, serial.summary.frames);
        assert_eq!(leader.summary.figures, serial.summary.figures, "{n} ranks");
        assert_eq!(
            files(&out),
            as_pieces(files(&dir.path().join("serial")), n),
            "{n} ranks"
        );
        frames_are_the_serial_frames(&dir.path().join("serial"), &out, n);
        assert_eq!(
            analysed(&out),
            analysed(&dir.path().join("serial")),
            "{n} ranks"
        );
        assert_eq!(
            every_column(&out),
            every_column(&dir.path().join("serial")),
            "{n} ranks"
        );
    }
}

/// `grains analyze RUN_DIR` of a run given a `[dispersal]` table afterwards (it reads
/// a `.pvtp` frame as its pieces joined): the frames analysed and each one's grains in
/// the band, transition and spall (counts: the sums follow the pieces' order).
fn analysed(run: &Path) -> Vec<u64> {
    let text = std::fs::read_to_string(run.join("scenario.toml")).unwrap();
    let with = format!("{text}\n[dispersal]\ncentre = [0.015, 0.0]\n");
    std::fs::write(run.join("scenario.toml"), with).unwrap();
    let out = run.join("analysis");
    let figures = grains_sim::dispersal::run_dir::analyze_run(run, &out, None).unwrap();
    std::fs::write(run.join("scenario.toml"), text).unwrap();
    std::fs::remove_dir_all(&out).unwrap();
    let d = &figures["dispersal"];
    let mut counts = vec![d["analysed"].as_u64().unwrap()];
    for f in d["frames"].as_array().unwrap() {
        for zone in ["band", "transition", "spall"] {
            counts.push(f["split"][zone]["grains"].as_u64().unwrap());
        }
    }
    counts
}

/// Each frame's values by particle id: (section, array) → id → the tuple's bits.
type ById = BTreeMap<(String, String), BTreeMap<u64, Vec<u64>>>;

fn by_id(pieces: &[Vec<ReadArray>]) -> ById {
    let mut all = ById::new();
    for arrays in pieces {
        let ids = &find_array(arrays, "PointData", "id").unwrap().values;
        for a in arrays.iter().filter(|a| a.section != "Verts") {
            let rows = all.entry((a.section.clone(), a.name.clone())).or_default();
            for (t, &id) in ids.iter().enumerate() {
                let tuple = &a.values[t * a.components..(t + 1) * a.components];
                let old = rows.insert(id as u64, tuple.iter().map(|x| x.to_bits()).collect());
                assert!(old.is_none(), "particle {id} in two pieces");
            }
        }
    }
    all
}

/// On `n` ranks every frame is a well-formed `.pvtp` over one piece per rank, which
/// `series.pvd` lists where the serial run lists its `.vtp`, and whose pieces together
/// hold the serial frame's particles, every array bit for bit but the contact stress,
/// a sum over contacts taken in the rank's list order (to 1e-12 of the largest).
fn frames_are_the_serial_frames(serial: &Path, out: &Path, n: usize) {
    let (serial, out) = (serial.join("frames"), out.join("frames"));
    let mut series = std::fs::read_to_string(serial.join("series.pvd")).unwrap();
    let mut k = 0;
    while serial.join(format!("particles_{k:05}.vtp")).exists() {
        let name = format!("particles_{k:05}");
        series = series.replace(&format!("\"{name}.vtp\""), &format!("\"{name}.pvtp\""));
        let (index, pieces) = check_pvtp(&out.join(format!("{name}.pvtp"))).unwrap();
        let want: Vec<String> = (0..n).map(|r| format!("{name}_r{r:03}.vtp")).collect();
        assert_eq!(index.pieces, want, "{n} ranks");
        let whole = read_appended_arrays(&serial.join(format!("{name}.vtp"))).unwrap();
        let (mut got, mut want) = (by_id(&pieces), by_id(&[whole]));
        let key = ("PointData".to_string(), "stress".to_string());
        let (a, b) = (got.remove(&key).unwrap(), want.remove(&key).unwrap());
        assert_eq!(got, want, "frame {k} on {n} ranks");
        let f = |bits: &Vec<u64>| -> Vec<f64> { bits.iter().map(|&b| f64::from_bits(b)).collect() };
        let scale = b.values().flat_map(f).fold(0.0f64, |m, x| m.max(x.abs()));
        assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
        for (x, y) in a.values().zip(b.values()) {
            for (x, y) in f(x).iter().zip(f(y)) {
                assert!(
                    (x - y).abs() <= 1e-12 * scale,
                    "stress, frame {k}: {x} vs {y}"
                );
            }
        }
        k += 1;
    }
    assert!(k > 2, "{k} frames");
    assert_eq!(
        std::fs::read_to_string(out.join("series.pvd")).unwrap(),
        series,
        "{n} ranks"
    );
}

/// Under several ranks, what the decomposition does not carry, and a grid that does not
/// match the rank count, are refused on every rank with one line, nothing written.
#[test]
fn what_ranks_cannot_run_is_refused_on_every_rank() {
    let dir = tempfile::tempdir().unwrap();
    let column = example("ranks_column.toml");
    let mut wrong = column.clone();
    wrong.text = wrong
        .text
        .replace("[run]", "[parallel]\nranks = [3, 1]\n\n[run]");
    let mut dispersing = column.clone();
    dispersing
        .text
        .push_str("\n[dispersal]\ncentre = [0.015, 0.0]\n");
    let cases = [
        (
            wrong,
            "parallel.ranks = [3, 1] makes 3 ranks, but the run has 2",
        ),
        (
            dispersing,
            "[dispersal] is not supported on several ranks yet",
        ),
    ];
    for (k, (src, want)) in cases.iter().enumerate() {
        refused_everywhere(src, 2, &dir.path().join(format!("case{k}")), want);
    }
    // One rank is refused a grid of several, too.
    let mut two = column.clone();
    two.text = two
        .text
        .replace("[run]", "[parallel]\nranks = [1, 2]\n\n[run]");
    let e = run::run(&two, RunOptions::new(dir.path().join("one"))).unwrap_err();
    assert!(
        e.to_string().contains("makes 2 ranks, but the run has 1"),
        "{e}"
    );
}

/// What a checkpoint in `dir` holds of the state, apart from the build positions (taken
/// where the writing run's list was built): every
/// particle field in storage order and the list's rows, partners and springs.
fn saved(dir: &Path, src: &Source) -> Vec<u64> {
    let file = dir.join("checkpoint.bin");
    let (_, bytes) = grains_sim::checkpoint::load(&file, &src.text).unwrap();
    let s = grains_dem::checkpoint::read(&mut bytes.as_slice(), 1 << 20).unwrap();
    let (p, c) = (&s.particles, &s.contacts);
    let mut w: Vec<u64> = p.id.iter().map(|&i| i as u64).collect();
    for v in [&p.pos, &p.vel, &p.force] {
        w.extend(v.iter().flat_map(|x| [x.x.to_bits(), x.y.to_bits()]));
    }
    for v in [&p.omega, &p.torque] {
        w.extend(v.iter().map(|x| x.to_bits()));
    }
    w.extend(c.row.iter().chain(&c.nbr).map(|&i| i as u64));
    w.extend(c.shear.iter().map(|x| x.to_bits()));
    w.extend(c.wall_shear.iter().map(|x| x.to_bits()));
    for l in &s.wall_loads {
        w.extend([l.force.x, l.force.y, l.torque].map(f64::to_bits));
        w.push(l.contacts as u64);
    }
    w.push(s.step);
    w.push(s.time.to_bits());
    w
}

/// The history without what a restart on another rank count may change: the neighbour
/// builds (the resumed run's list starts at the checkpoint, so it is rebuilt at other
/// steps; the forces do not depend on when).
fn restart_invariant(dir: &Path) -> Vec<Vec<String>> {
    columns_but(dir, |c| c == "neighbour_builds")
}

/// A run stopped with a checkpoint on one rank count and resumed on another ends as the
/// straight serial run: the same state hash on every rank, the same history figures.
#[test]
fn a_checkpoint_resumes_on_any_rank_count_as_the_straight_run() {
    let src = example("ranks_column.toml");
    let dir = tempfile::tempdir().unwrap();
    let at = |name: &str| dir.path().join(name);
    let straight = run::run(&src, RunOptions::new(at("straight"))).unwrap();
    let want = straight.summary.state_hash.clone();
    let stop = straight.summary.steps / 2 + 7;
    let paused = |n: usize, out: &Path| {
        let mut opts = RunOptions::new(out);
        opts.stop_at_step = Some(stop);
        if n == 1 {
            return run::run(&src, opts).map(|d| d.status.name());
        }
        let done = on_ranks_with(n, |l| {
            let mut opts = RunOptions::new(out);
            opts.stop_at_step = Some(stop);
            run::run_on(&src, opts, l)
        });
        let names: Vec<_> = done.into_iter().map(|d| d.unwrap().status.name()).collect();
        assert!(names.iter().all(|&s| s == names[0]), "{names:?}");
        Ok(names[0])
    };
    let check = |out: &Path, d: &Finished, what: &str| {
        assert_eq!(d.summary.state_hash, want, "{what}");
        assert_eq!(d.status, straight.status, "{what}");
        assert_eq!(d.summary.figures, straight.summary.figures, "{what}");
        assert_eq!(
            restart_invariant(out),
            restart_invariant(&at("straight")),
            "{what}"
        );
    };
    // On 2 ranks, every rank with the straight run's hash.
    let on_2 = |name: &str, what: &str| {
        let d = at(name);
        let done = on_ranks_with(2, |l| run::resume_on(&d, RunOptions::new(&d), l));
        check(&d, &hashed(done, &want, what), what);
    };
    // Checkpointed on 4 ranks: resumed on 2, and on 1 (the serial resume).
    assert_eq!(paused(4, &at("four")).unwrap(), "paused");
    let written_by_4 = saved(&at("four"), &src);
    copy_dir(&at("four"), &at("four_on_1"));
    on_2("four", "4 ranks, resumed on 2");
    let on1 = run::resume(&at("four_on_1"), RunOptions::new(at("four_on_1"))).unwrap();
    check(&at("four_on_1"), &on1, "4 ranks, resumed on 1");
    // The checkpoint file does not depend on the rank count that wrote it.
    assert_eq!(paused(2, &at("two")).unwrap(), "paused");
    assert!(
        saved(&at("two"), &src) == written_by_4,
        "the checkpoints of 2 and 4 ranks differ"
    );
    // A serial checkpoint resumed on 2 ranks.
    assert_eq!(paused(1, &at("one")).unwrap(), "paused");
    on_2("one", "1 rank, resumed on 2");
}

/// A checkpoint beside another scenario than the one it was written for is refused on
/// every rank with one line.
#[test]
fn a_checkpoint_of_another_scenario_is_refused_on_every_rank() {
    let src = example("ranks_column.toml");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let mut opts = RunOptions::new(&out);
    opts.stop_at_step = Some(20);
    assert_eq!(run::run(&src, opts).unwrap().status.name(), "paused");
    let copy = out.join("scenario.toml");
    let text = std::fs::read_to_string(&copy).unwrap();
    std::fs::write(&copy, text.replace("speed = 0.05", "speed = 0.06")).unwrap();
    for (r, got) in on_ranks_with(2, |l| run::resume_on(&out, RunOptions::new(&out), l))
        .into_iter()
        .enumerate()
    {
        let e = got.err().unwrap_or_else(|| panic!("rank {r}: resumed"));
        assert!(
            e.contains("belongs to a different scenario") && !e.contains('\n'),
            "rank {r}: {e}"
        );
    }
}

/// A progress display that raises `flag` once the run reaches step `at`: a signal
/// arriving on one rank at a step of its own.
struct RaiseAt<'a> {
    at: u64,
    flag: &'a AtomicBool,
}

impl Progress for RaiseAt<'_> {
    fn update(&mut self, _done: f64, clock: Clock) {
        if clock.step >= self.at {
            self.flag.store(true, Ordering::SeqCst);
        }
    }
}

/// A progress display that puts a directory where the run will write `file` once the
/// run reaches step `at` (so that the write fails, even for root).
struct BlockAt {
    at: u64,
    file: PathBuf,
}

impl Progress for BlockAt {
    fn update(&mut self, _done: f64, clock: Clock) {
        if clock.step >= self.at {
            std::fs::create_dir_all(self.file.join("in_the_way")).unwrap();
        }
    }
}

/// Ctrl-C or SIGTERM on one rank only: every rank stops at the same step (the first
/// agreement step at or after it), rank 0 writes one checkpoint, every rank ends
/// interrupted, and the checkpoint resumes to the straight run's state hash.
#[test]
fn a_signal_on_one_rank_stops_every_rank_at_the_same_step() {
    let src = example("ranks_column.toml");
    let dir = tempfile::tempdir().unwrap();
    let straight = run::run(&src, RunOptions::new(dir.path().join("straight"))).unwrap();
    let out = dir.path().join("interrupted");
    let at = straight.summary.steps / 2 + 5;
    let flags = [AtomicBool::new(false), AtomicBool::new(false)];
    let done = on_ranks_with(2, |l| {
        let r = l.rank();
        let mut opts = RunOptions::new(&out);
        opts.interrupt = Some(&flags[r]);
        if r == 1 {
            opts.progress = Box::new(RaiseAt {
                at,
                flag: &flags[1],
            });
        }
        run::run_on(&src, opts, l)
    });
    let want = at.next_multiple_of(AGREE_EVERY);
    for (r, d) in done.iter().enumerate() {
        let d = d.as_ref().unwrap_or_else(|e| panic!("rank {r}: {e}"));
        assert_eq!(d.status.name(), "interrupted", "rank {r}");
        assert_eq!(d.summary.steps, want, "rank {r}");
    }
    assert!(
        !flags[0].load(Ordering::SeqCst),
        "rank 0 never got the signal"
    );
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("\"interrupted\""), "{summary}");
    let resumed = on_ranks_with(2, |l| run::resume_on(&out, RunOptions::new(&out), l));
    hashed(resumed, &straight.summary.state_hash, "resumed on 2 ranks");
}

/// Every rank's error, each one line: rank 0's names `what`, the others point at rank 0.
fn failed_together(done: Vec<Result<Finished, String>>, what: &str) {
    for (r, d) in done.into_iter().enumerate() {
        let e = d.err().unwrap_or_else(|| panic!("rank {r}: no error"));
        let want = if r == 0 {
            what
        } else {
            "rank 0 could not write"
        };
        assert!(e.contains(want) && !e.contains('\n'), "rank {r}: {e}");
    }
}

/// A write that fails on rank 0 (which alone writes) fails every rank at the same point,
/// with one message on rank 0, rather than leaving the others waiting for it: at the
/// start (the output directory), at a checkpoint, and at the end (the summary).
#[test]
fn a_failed_write_on_rank_0_stops_every_rank() {
    let src = example("ranks_column.toml");
    let dir = tempfile::tempdir().unwrap();
    // At the start: a stale checkpoint that cannot be removed.
    let out = dir.path().join("start");
    std::fs::create_dir_all(out.join("checkpoint.bin/in_the_way")).unwrap();
    let done = on_ranks_with(2, |l| run::run_on(&src, RunOptions::new(&out), l));
    failed_together(done, "checkpoint.bin");
    // At a checkpoint half-way.
    let out = dir.path().join("checkpoint");
    let done = on_ranks_with(2, |l| {
        let mut opts = RunOptions::new(&out);
        opts.stop_at_step = Some(100);
        if l.rank() == 0 {
            opts.progress = Box::new(BlockAt {
                at: 100,
                file: out.join("checkpoint.bin"),
            });
        }
        run::run_on(&src, opts, l)
    });
    failed_together(done, "checkpoint.bin");
    // At the end.
    let out = dir.path().join("end");
    std::fs::create_dir_all(out.join("summary.json/in_the_way")).unwrap();
    let done = on_ranks_with(2, |l| run::run_on(&src, RunOptions::new(&out), l));
    failed_together(done, "summary.json");
}
