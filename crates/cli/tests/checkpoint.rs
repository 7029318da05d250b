//! Checkpoints through the binary: a run paused and resumed ends bitwise where a straight
//! run ends; damaged checkpoints are refused with a clear error.

mod common;
use common::*;
use std::path::Path;
use std::process::Command;

const SCENARIO: &str = r#"
name = "ck"
gravity = [0.0, -9.81]

[domain]
lo = [0.0, 0.0]
hi = [0.03, 0.06]
periodic = [true, false]

[[material]]
name = "soft"
density = 2500.0
youngs = 5.0e6
poisson = 0.3
restitution = 0.5
friction = 0.4

[[particles]]
source = "lattice"
material = "soft"
region = { lo = [0.0, 0.001], hi = [0.03, 0.05] }
count = 300
radius = { distribution = "uniform", min = 0.0005, max = 0.0007 }
speed = 0.1
seed = 3

[[wall]]
name = "floor"
shape = "segment"
a = [-1.0, 0.0]
b = [1.0, 0.0]

[run]
duration = 0.02
safety = 0.2

[output]
frames = 10
history = 50
checkpoint_every = 500
lammps_dump = true
"#;

/// `grains ARGS`: (exit code, stderr).
fn run(args: &[&str]) -> (i32, String) {
    let o = grains(args);
    (o.code, o.stderr)
}

fn summary_in(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// A copy of a run directory's files (frames left out).
fn copy_run(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for f in [
        "scenario.toml",
        "summary.json",
        "history.csv",
        "checkpoint.bin",
    ] {
        std::fs::copy(from.join(f), to.join(f)).unwrap();
    }
}

#[test]
fn pause_and_resume_match_a_straight_run() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("ck.toml");
    std::fs::write(&file, SCENARIO).unwrap();
    let (a, b) = (tmp.path().join("straight"), tmp.path().join("paused"));
    let f = file.to_str().unwrap();
    let (code, err) = run(&["run", f, "--out", a.to_str().unwrap(), "--threads", "1"]);
    assert_eq!(code, 0, "{err}");
    let (code, err) = run(&[
        "run",
        f,
        "--out",
        b.to_str().unwrap(),
        "--stop-at-step",
        "777",
        "--threads",
        "2",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(summary_in(&b)["status"], "paused");
    let damaged = tmp.path().join("damaged");
    copy_run(&b, &damaged);
    let (code, err) = run(&["resume", b.to_str().unwrap(), "--threads", "2"]);
    assert_eq!(code, 0, "{err}");
    let (sa, sb) = (summary_in(&a), summary_in(&b));
    assert_eq!(sb["status"], "completed");
    assert_eq!(sa["steps"], sb["steps"]);
    assert_eq!(
        sa["state_hash"], sb["state_hash"],
        "resumed run differs from the straight run"
    );
    assert_eq!(sa["frames"], sb["frames"]);
    let rows = |d: &Path| {
        std::fs::read_to_string(d.join("history.csv"))
            .unwrap()
            .lines()
            .count()
    };
    assert_eq!(rows(&a), rows(&b));
    // The OVITO dump sits beside each VTP frame.
    assert!(a.join("frames/particles_00000.dump").exists());
    let dump = std::fs::read_to_string(a.join("frames/particles_00001.dump")).unwrap();
    assert!(dump.contains("ITEM: ATOMS id type x y z radius vx vy vz omegaz fx fy fz"));
    assert_eq!(dump.lines().count(), 9 + 300);

    // A finished run is not resumed; a new run into its directory starts afresh, with
    // no stale checkpoint left behind.
    let (code, err) = run(&["resume", b.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("already finished"), "{err}");
    let stale = tmp.path().join("stale");
    copy_run(&damaged, &stale);
    let plain = tmp.path().join("plain.toml");
    std::fs::write(&plain, SCENARIO.replace("checkpoint_every = 500\n", "")).unwrap();
    let p = plain.to_str().unwrap();
    let (code, err) = run(&["run", p, "--out", stale.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(
        !stale.join("checkpoint.bin").exists(),
        "a stale checkpoint was left"
    );

    // A truncated or corrupted checkpoint is refused with a clear error.
    let b = damaged;
    let ck = b.join("checkpoint.bin");
    let bytes = std::fs::read(&ck).unwrap();
    std::fs::write(&ck, &bytes[..bytes.len() / 2]).unwrap();
    let (code, err) = run(&["resume", b.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("corrupted or truncated"), "{err}");
    let mut flipped = bytes.clone();
    flipped[bytes.len() / 3] ^= 0x40;
    std::fs::write(&ck, &flipped).unwrap();
    let (code, err) = run(&["resume", b.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("checksum"), "{err}");
    std::fs::write(&ck, b"not a checkpoint").unwrap();
    let (code, err) = run(&["resume", b.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("not a grains checkpoint"), "{err}");

    // One of an older format (4: before the walls' poses were kept), its checksum
    // whole, is refused in one line naming its version.
    let mut old = bytes[..bytes.len() - 8].to_vec();
    old[8..12].copy_from_slice(&4u32.to_le_bytes());
    let sum = old.iter().fold(0xcbf29ce484222325u64, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x100000001b3)
    });
    old.extend_from_slice(&sum.to_le_bytes());
    std::fs::write(&ck, &old).unwrap();
    let (code, err) = run(&["resume", b.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("checkpoint format version 4"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
}

#[test]
fn sigterm_writes_a_checkpoint_and_resume_goes_on_exactly() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("ck.toml");
    // Long enough that the signal always arrives mid-run.
    std::fs::write(
        &file,
        SCENARIO.replace("duration = 0.02", "duration = 50.0"),
    )
    .unwrap();
    let (a, b) = (tmp.path().join("signalled"), tmp.path().join("straight"));
    let mut child = Command::new(env!("CARGO_BIN_EXE_grains"))
        .args(["run", file.to_str().unwrap(), "--out", a.to_str().unwrap()])
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let killed = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130));
    let s = summary_in(&a);
    assert_eq!(s["status"], "interrupted");
    let stop = s["steps"].as_u64().unwrap() + 123;
    let stop = stop.to_string();
    let (code, err) = run(&["resume", a.to_str().unwrap(), "--stop-at-step", &stop]);
    assert_eq!(code, 0, "{err}");
    let (code, err) = run(&[
        "run",
        file.to_str().unwrap(),
        "--out",
        b.to_str().unwrap(),
        "--stop-at-step",
        &stop,
    ]);
    assert_eq!(code, 0, "{err}");
    let (sa, sb) = (summary_in(&a), summary_in(&b));
    assert_eq!(sa["steps"], sb["steps"]);
    assert_eq!(sa["state_hash"], sb["state_hash"]);
}

/// The FEM–DEM case of the library's tests (a 2 mm PE4 charge in a ring of 0.1 mm disks).
const RING: &str = include_str!("../../sim/tests/data/ring_tiny.toml");

#[test]
fn coupled_run_paused_and_resumed_matches_a_straight_run() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("ring.toml");
    let text = RING.replace(
        "snapshots = [2.0e-6]\n",
        "snapshots = [2.0e-6]\ncheckpoint_every = 100\n",
    );
    assert_ne!(text, RING);
    std::fs::write(&file, text).unwrap();
    let f = file.to_str().unwrap();
    let (a, b) = (tmp.path().join("straight"), tmp.path().join("paused"));
    let (code, err) = run(&["run", f, "--out", a.to_str().unwrap(), "--threads", "1"]);
    assert_eq!(code, 0, "{err}");
    let (code, err) = run(&[
        "run",
        f,
        "--out",
        b.to_str().unwrap(),
        "--stop-at-step",
        "555",
        "--threads",
        "2",
    ]);
    assert_eq!(code, 0, "{err}");
    let paused = summary_in(&b);
    assert_eq!(paused["status"], "paused");
    assert!(paused["message"]
        .as_str()
        .unwrap()
        .contains("grains resume"));
    let (code, err) = run(&["resume", b.to_str().unwrap(), "--threads", "2"]);
    assert_eq!(code, 0, "{err}");
    let (sa, sb) = (summary_in(&a), summary_in(&b));
    assert_eq!(sb["status"], "completed");
    assert_eq!(sa["steps"], sb["steps"]);
    assert_eq!(
        sa["state_hash"], sb["state_hash"],
        "resumed coupled run differs from the straight run"
    );
    assert_eq!(sa["frames"], sb["frames"]);
    assert_eq!(sa["figures"], sb["figures"]);
    let history = |d: &Path| std::fs::read_to_string(d.join("history.csv")).unwrap();
    assert_eq!(history(&a), history(&b), "history differs after resume");
}

/// A coupled run whose ring comes from a file named relative to its scenario resumes
/// from the scenario copy in its output directory: the checkpoint records where the
/// original's relative paths started.
#[test]
fn coupled_run_resumes_with_its_files_where_the_scenario_named_them() {
    let tmp = tempfile::tempdir().unwrap();
    let case = tmp.path().join("case");
    std::fs::create_dir_all(&case).unwrap();
    let mut disks = String::from("# x y r\n");
    let (pitch, r) = (0.1e-3, 0.045e-3);
    for row in -40i32..=40 {
        for col in -40i32..=40 {
            let x = (col as f64 + 0.5 * (row & 1) as f64) * pitch;
            let y = row as f64 * pitch * 3f64.sqrt() / 2.0;
            let rho = (x * x + y * y).sqrt();
            if rho - r >= 2.0e-3 && rho + r <= 2.8e-3 {
                disks.push_str(&format!("{x:e} {y:e} {r:e}\n"));
            }
        }
    }
    std::fs::write(case.join("disks.txt"), disks).unwrap();
    let text = RING
        .replace(
            "[ring.packing]\nsource = \"lattice\"\nd0 = 0.1e-3\n",
            "[ring.packing]\nsource = \"file\"\npath = \"disks.txt\"\n",
        )
        .replace(
            "snapshots = [2.0e-6]\n",
            "snapshots = [2.0e-6]\ncheckpoint_every = 100\n",
        )
        .replace("expected = 1.15", "expected = 1.0")
        .replace("tolerance = 0.1", "tolerance = 0.5");
    assert!(text.contains("path = \"disks.txt\""));
    let file = case.join("ring.toml");
    std::fs::write(&file, text).unwrap();
    let f = file.to_str().unwrap();
    let (a, b) = (tmp.path().join("straight"), tmp.path().join("paused"));
    let (code, err) = run(&["run", f, "--out", a.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let (code, err) = run(&[
        "run",
        f,
        "--out",
        b.to_str().unwrap(),
        "--stop-at-step",
        "300",
    ]);
    assert_eq!(code, 0, "{err}");
    // What a run killed while writing a checkpoint leaves behind goes at the resume.
    let cut = b.join(".checkpoint.bin.tmp.12345.0.bin");
    std::fs::write(&cut, b"half a checkpoint").unwrap();
    let (code, err) = run(&["resume", b.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(!cut.exists(), "a cut-short checkpoint was left behind");
    let (sa, sb) = (summary_in(&a), summary_in(&b));
    assert_eq!(sb["status"], "completed");
    assert_eq!(sa["state_hash"], sb["state_hash"]);
}
