//! 3D runs through the binary: checkpoints (`[output] checkpoint_every`, `--stop-at-step`)
//! and `grains resume` continue a run bitwise, the collision checks included; the
//! LAMMPS dump beside each frame.

mod common;
use common::*;
use std::path::Path;

/// The settling column, short, with checkpoints and the dump.
fn column() -> String {
    let text = std::fs::read_to_string(example("dem3d/settling_column.toml")).unwrap();
    text.replace("duration = 1.5", "duration = 0.02")
        .replace("stop_kinetic_ratio = 1.0e-6", "")
        .replace(
            "[output]\nframes = 20\nhistory = 400",
            "[output]\nframes = 4\nhistory = 40\ncheckpoint_every = 300\nlammps_dump = true",
        )
        .replace("tolerance = 0.005", "tolerance = 1.0")
        // 0.02 s in, the ledger has booked little: its closure is a larger share.
        .replace("max = 0.01", "max = 1.0")
}

fn summary_in(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// Runs `file` straight into `a` (1 thread), and into `b` paused half way (2 threads)
/// then resumed; returns both summaries.
fn straight_and_resumed(file: &Path, a: &Path, b: &Path) -> (serde_json::Value, serde_json::Value) {
    let f = file.to_str().unwrap();
    let o = grains(&["run", f, "--out", a.to_str().unwrap(), "--threads", "1"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let stop = (summary_in(a)["steps"].as_u64().unwrap() / 2 + 7).to_string();
    let o = grains(&[
        "run",
        f,
        "--out",
        b.to_str().unwrap(),
        "--stop-at-step",
        &stop,
        "--threads",
        "2",
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let paused = summary_in(b);
    assert_eq!(paused["status"], "paused", "{paused}");
    assert!(b.join("checkpoint.bin").is_file());
    let o = grains(&["resume", b.to_str().unwrap(), "--threads", "2"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    (summary_in(a), summary_in(b))
}

#[test]
fn a_paused_3d_run_resumes_bitwise() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("column.toml");
    std::fs::write(&file, column()).unwrap();
    let (a, b) = (tmp.path().join("straight"), tmp.path().join("paused"));
    let (sa, sb) = straight_and_resumed(&file, &a, &b);
    assert_eq!(sb["status"], "completed");
    assert_eq!(sa["steps"], sb["steps"]);
    assert_eq!(sa["state_hash"], sb["state_hash"], "resumed 3D run differs");
    // The ledger rides in the checkpoint: the resumed run's books are the straight one's.
    assert_eq!(
        sa["figures"]["energy_ledger"], sb["figures"]["energy_ledger"],
        "resumed ledger differs"
    );
    assert_eq!(sa["frames"], sb["frames"]);
    assert_eq!(sa["checks"], sb["checks"]);
    let rows = |d: &Path| {
        std::fs::read_to_string(d.join("history.csv"))
            .unwrap()
            .lines()
            .count()
    };
    assert_eq!(rows(&a), rows(&b));

    // The OVITO dump: LAMMPS's `dump custom` layout, one line per sphere in id order.
    let dump = std::fs::read_to_string(a.join("frames/particles_00001.dump")).unwrap();
    let lines: Vec<&str> = dump.lines().collect();
    assert_eq!(lines[2], "ITEM: NUMBER OF ATOMS");
    assert_eq!(lines[3], "400");
    assert_eq!(lines[4], "ITEM: BOX BOUNDS pp pp ff");
    assert_eq!(
        lines[8],
        "ITEM: ATOMS id type x y z vx vy vz omegax omegay omegaz radius fx fy fz"
    );
    assert_eq!(lines.len(), 9 + 400);
    let first: Vec<f64> = lines[9].split(' ').map(|x| x.parse().unwrap()).collect();
    assert_eq!(first.len(), 15);
    assert_eq!((first[0], first[1]), (1.0, 1.0));
    assert!(
        (0.0018..=0.002).contains(&first[11]),
        "radius {}",
        first[11]
    );
    assert!(b.join("frames/particles_00004.dump").is_file());
}

/// Paused in the middle of Chung & Ooi's test 1 (a sphere on a sphere), the resumed run
/// ends with the straight run's state and check values: the collision probes are part
/// of the checkpoint.
#[test]
fn a_3d_collision_resumed_keeps_its_checks() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("test1.toml");
    let text = std::fs::read_to_string(example("dem3d/chung_ooi_test1.toml")).unwrap();
    std::fs::write(&file, text).unwrap();
    let (a, b) = (tmp.path().join("straight"), tmp.path().join("paused"));
    let (sa, sb) = straight_and_resumed(&file, &a, &b);
    assert_eq!(sa["state_hash"], sb["state_hash"]);
    assert_eq!(sa["checks"], sb["checks"]);
    for c in sb["checks"].as_array().unwrap() {
        assert_eq!(c["pass"], true, "{c}");
    }
}

/// A wall that moves is where the straight run's steps left it after a resume: the
/// column's floor rising under it (the checkpoint keeps each wall's pose, which the
/// resumed run places the wall at).
#[test]
fn a_moving_wall_resumed_is_where_the_straight_run_left_it() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("piston.toml");
    let text = column().replace(
        "normal = [0.0, 0.0, 1.0]\n",
        "normal = [0.0, 0.0, 1.0]\nvelocity = [0.0, 0.0, 0.05]\n",
    );
    assert!(text.contains("velocity = [0.0, 0.0, 0.05]"));
    std::fs::write(&file, text).unwrap();
    let (a, b) = (tmp.path().join("straight"), tmp.path().join("paused"));
    let (sa, sb) = straight_and_resumed(&file, &a, &b);
    assert_eq!(sa["state_hash"], sb["state_hash"], "resumed piston differs");
    let last = |d: &Path| {
        let h = std::fs::read_to_string(d.join("history.csv")).unwrap();
        h.lines().last().unwrap().to_string()
    };
    assert_eq!(last(&a), last(&b));
}

/// The small drum paused and resumed: its angle of repose and torque average the
/// samples from before the pause too (the drum's watch is part of the checkpoint).
#[test]
fn a_3d_drum_resumed_keeps_its_samples() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("drum.toml");
    let text = std::fs::read_to_string(example("dem3d/drum_small.toml")).unwrap();
    let short = text
        .replace("duration = 1.6", "duration = 0.4")
        .replace("after = 0.8", "after = 0.1");
    assert_eq!(short.matches("after = 0.1").count(), 2);
    std::fs::write(&file, short).unwrap();
    let (a, b) = (tmp.path().join("straight"), tmp.path().join("paused"));
    let (sa, sb) = straight_and_resumed(&file, &a, &b);
    assert_eq!(sa["state_hash"], sb["state_hash"]);
    assert_eq!(sa["checks"], sb["checks"], "resumed drum's checks differ");
    assert_eq!(sb["checks"].as_array().unwrap().len(), 2);
}

/// A run that pours spheres, paused while it pours, resumes bitwise: the pour's
/// progress is read back from the ids in the checkpoint, and its places are drawn from
/// streams of the step and the sphere's number.
#[test]
fn a_paused_pour_resumes_bitwise() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("pour.toml");
    let text = std::fs::read_to_string(example("dem3d/pour_small.toml")).unwrap();
    let text = text
        .replace("duration = 1.0", "duration = 0.06")
        .replace(
            "[output]\nframes = 10\nhistory = 200",
            "[output]\nframes = 3\nhistory = 20\ncheckpoint_every = 200",
        )
        .replace("tolerance = 0.005", "tolerance = 1.0");
    std::fs::write(&file, text).unwrap();
    let (a, b) = (tmp.path().join("straight"), tmp.path().join("paused"));
    let (sa, sb) = straight_and_resumed(&file, &a, &b);
    assert_eq!(sb["status"], "completed");
    let poured = sa["poured"].as_u64().unwrap();
    assert!(poured > 50 && poured < 300, "poured {poured}");
    assert_eq!(sa["poured"], sb["poured"]);
    assert_eq!(sa["state_hash"], sb["state_hash"], "resumed pour differs");
    assert_eq!(sa["checks"], sb["checks"]);
}

/// The small column paused after its tube's release and resumed: the resumed run opens
/// with the tube gone (the release depends on the time alone) and keeps the column's
/// height measured before the pause.
#[test]
fn a_released_column_resumes_bitwise() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("collapse.toml");
    let text = std::fs::read_to_string(example("dem3d/collapse_small.toml")).unwrap();
    let short = text
        .replace("duration = 0.8", "duration = 0.3")
        .replace("release = 0.3", "release = 0.12")
        .replace("tolerance = 0.15", "tolerance = 10.0");
    assert_ne!(short, text);
    std::fs::write(&file, short).unwrap();
    let (a, b) = (tmp.path().join("straight"), tmp.path().join("paused"));
    let (sa, sb) = straight_and_resumed(&file, &a, &b);
    assert_eq!(
        sa["state_hash"], sb["state_hash"],
        "resumed collapse differs"
    );
    assert_eq!(sa["checks"], sb["checks"]);
    assert_eq!(sa["figures"], sb["figures"]);
}
