//! The cases of issue 27 one by one: outputs stay where the user put them, bad physics
//! stops the run or is refused, implausible values are warned about with their figure,
//! and every refusal is exit 1 with one line. (`refusals.rs` replays the long list.)

mod common;
use common::*;

/// One disk resting 0.1 mm above a floor.
const BASE: &str = ONE_DISK;

/// `grains run` without `--out` in `root/a/b`: a name that would climb out, or an
/// absolute one, is refused and nothing appears anywhere under `root`, nor at the
/// absolute path.
#[test]
fn a_name_cannot_move_the_outputs() {
    let abs = std::env::temp_dir().join(format!("grains_escape_{}", std::process::id()));
    let abs_name = abs.display().to_string();
    for name in [
        "../../escaped",
        abs_name.as_str(),
        "",
        "a/b",
        "..",
        "bad\\tname",
    ] {
        let root = tempfile::tempdir().unwrap();
        let work = root.path().join("a/b");
        std::fs::create_dir_all(&work).unwrap();
        let text = BASE.replace("name = \"bad\"", &format!("name = \"{name}\""));
        std::fs::write(work.join("s.toml"), text).unwrap();
        let o = grains_in(Some(&work), &["run", "s.toml"]);
        assert_eq!(o.code, 1, "{name}: {}", o.stderr);
        assert_eq!(o.stderr.lines().count(), 1, "{}", o.stderr);
        assert!(o.stderr.contains("name = "), "{}", o.stderr);
        assert!(!root.path().join("escaped").exists());
        assert!(!work.join("runs").exists());
        assert!(!abs.exists(), "wrote at the absolute path");
        let left: Vec<_> = std::fs::read_dir(root.path()).unwrap().collect();
        assert_eq!(left.len(), 1, "only a/ in the root");
    }
}

/// A disk 0.8 r inside the floor is refused by `run` and reported by `check`.
#[test]
fn a_disk_inside_a_wall_is_refused() {
    let text = BASE.replace("at = [0.005, 0.0006]", "at = [0.005, 0.0001]");
    refused(&text, &["particle 0", "floor", "0.5 of its radius"]);
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), &text).unwrap();
    let o = grains_in(Some(dir.path()), &["check", "s.toml"]);
    assert_eq!(o.code, 1, "{}", o.stderr);
    assert!(o.stderr.contains("floor"), "{}", o.stderr);
}

/// Gravity of −1e12 m/s² drives the disk through the floor: the run stops unstable
/// (exit 3) with a message, and keeps what it wrote before.
#[test]
fn falling_through_the_floor_stops_the_run() {
    let text = BASE.replace("gravity = [0.0, -9.81]", "gravity = [0.0, -1.0e12]");
    let (o, dir) = run_text(&text, &[], &[]);
    assert_eq!(o.code, 3, "{}", o.stderr);
    assert!(o.stderr.contains("runaway overlap"), "{}", o.stderr);
    assert!(o.stderr.contains("warning: gravity"), "{}", o.stderr);
    let s = summary(dir.path());
    assert_eq!(s["status"], "unstable");
    assert!(dir.path().join("out/history.csv").exists());
}

/// A disk thrown down with no floor leaves the domain: the run stops unstable instead
/// of reporting "completed" with the disk gone.
#[test]
fn leaving_the_domain_stops_the_run() {
    let text = BASE
        .replace("[[wall]]\nname = \"floor\"", "[[wall]]\nname = \"lid\"")
        .replace(
            "a = [0.0, 0.0]\nb = [0.01, 0.0]",
            "a = [0.0, 0.01]\nb = [0.01, 0.01]",
        )
        .replace(
            "radius = 0.0005 }",
            "radius = 0.0005, velocity = [0.0, -10.0] }",
        )
        .replace("duration = 1.0e-7", "duration = 1.0e-4");
    let (o, dir) = run_text(&text, &[], &[]);
    assert_eq!(o.code, 3, "{}", o.stderr);
    assert!(o.stderr.contains("left the domain"), "{}", o.stderr);
    assert_eq!(o.stderr.matches("error").count(), 1, "{}", o.stderr);
    assert_eq!(summary(dir.path())["status"], "unstable");
}

/// Legal but implausible values: `check` and `run` warn with the figure.
#[test]
fn implausible_values_are_warned_about() {
    for (from, to, figure) in [
        ("friction = 0.3", "friction = 50.0", "friction = 50"),
        (
            "radius = 0.0005 }",
            "radius = 0.0005, velocity = [1.0e5, 0.0] }",
            "100000 m/s",
        ),
    ] {
        let text = BASE.replace(from, to);
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("s.toml"), &text).unwrap();
        let o = grains_in(Some(dir.path()), &["check", "s.toml"]);
        let warning = o.stdout.lines().find(|l| l.starts_with("warning"));
        assert!(
            warning.is_some_and(|w| w.contains(figure)),
            "{figure}: {}",
            o.stdout
        );
        let o = grains_in(Some(dir.path()), &["run", "s.toml", "--out", "out"]);
        assert!(
            o.stderr.contains("warning") && o.stderr.contains(figure),
            "{figure}: {}",
            o.stderr
        );
    }
}

/// `dt` and `safety` together are refused: one of them would be ignored.
#[test]
fn dt_and_safety_together_are_refused() {
    let text = BASE.replace(
        "duration = 1.0e-7",
        "duration = 1.0e-7\ndt = 1.0e-9\nsafety = 0.5",
    );
    refused(&text, &["run.safety", "run.dt"]);
}

/// clap's refusals are exit 1 with one line, like every other bad input; `--help` is 0.
#[test]
fn argument_errors_are_exit_1_and_one_line() {
    for args in [
        &["run", "--frobnicate"][..],
        &["run", "s.toml", "--threads", "many"],
        &["frobnicate"],
        &["bench"],
        &[],
    ] {
        let o = grains(args);
        assert_eq!(o.code, 1, "{args:?}: {}", o.stderr);
        assert_eq!(o.stderr.trim().lines().count(), 1, "{args:?}: {}", o.stderr);
        assert!(o.stderr.starts_with("grains: error:"), "{}", o.stderr);
    }
    assert_eq!(grains(&["--help"]).code, 0);
    assert_eq!(grains(&["--version"]).code, 0);
}

/// `bench` with nothing to time is refused.
#[test]
fn bench_without_steps_is_refused() {
    for what in ["dem", "mpm"] {
        let o = grains(&["bench", what, "--steps", "0", "--particles", "100"]);
        assert_eq!(o.code, 1, "{}", o.stderr);
        assert!(o.stderr.contains("--steps = 0"), "{}", o.stderr);
    }
}

/// `pack --out` onto a file, or under one, is refused before the packing is made.
#[test]
fn pack_into_a_file_is_refused_before_packing() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("p.toml"),
        "name = \"p\"\n[domain]\nshape = \"disk\"\nradius = 0.01\n[sizes]\ndistribution = \"uniform\"\nd0 = 1e-4\ndelta = 0.1\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("file"), "").unwrap();
    for out in ["file", "file/sub"] {
        let started = std::time::Instant::now();
        let o = grains_in(Some(dir.path()), &["pack", "p.toml", "--out", out]);
        assert_eq!(o.code, 1, "{}", o.stderr);
        assert!(o.stderr.contains("not a directory"), "{}", o.stderr);
        assert!(started.elapsed().as_secs_f64() < 5.0, "it packed first");
    }
}

/// `analyze RUN_DIR --times` reads negative numbers as numbers and refuses times outside
/// the run's frames; the frame spacing that limits event times is reported.
#[test]
fn analyze_times_outside_the_run_are_refused() {
    let text = BASE
        .replace("gravity = [0.0, -9.81]", "gravity = [0.0, 0.0]")
        .replace(
            "disks = [{ at = [0.005, 0.0006], radius = 0.0005 }]",
            "disks = [{ at = [0.004, 0.005], radius = 0.0004, velocity = [-1.0, 0.0] }, { at = [0.006, 0.005], radius = 0.0004, velocity = [1.0, 0.0] }, { at = [0.005, 0.004], radius = 0.0004, velocity = [0.0, -1.0] }, { at = [0.005, 0.006], radius = 0.0004, velocity = [0.0, 1.0] }]",
        )
        .replace("duration = 1.0e-7", "duration = 1.0e-6\n[output]\nframes = 4")
        + "\n[dispersal]\ncentre = [0.005, 0.005]\n";
    let (o, dir) = run_text(&text, &[], &[]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let out = dir.path().join("out");
    let run = out.to_str().unwrap();
    for t in ["-1e-6", "5e-6"] {
        let o = grains(&["analyze", run, "--times", t, "--out", "never"]);
        assert_eq!(o.code, 1, "{t}: {}", o.stderr);
        assert!(
            o.stderr.contains("outside the run's frames"),
            "{}",
            o.stderr
        );
        assert!(!std::path::Path::new("never").exists());
    }
    let o = grains(&["analyze", run, "--json"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let v: serde_json::Value = serde_json::from_str(&o.stdout).unwrap();
    assert!(v["frame_spacing_s"].as_f64().unwrap() > 0.0, "{v}");
    assert!(v["event_times_resolution"]
        .as_str()
        .unwrap()
        .contains("frame spacing"));
}

/// An output file that cannot be written is named, once, in the one error line.
#[test]
fn a_write_error_names_its_path() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("out/history.csv")).unwrap();
    std::fs::write(dir.path().join("s.toml"), BASE).unwrap();
    let o = grains_in(Some(dir.path()), &["run", "s.toml", "--out", "out"]);
    assert_eq!(o.code, 1, "{}", o.stderr);
    let errors: Vec<&str> = o.stderr.lines().filter(|l| l.contains("error")).collect();
    assert_eq!(errors.len(), 1, "{}", o.stderr);
    assert_eq!(
        errors[0].matches("out/history.csv").count(),
        1,
        "{}",
        errors[0]
    );
}

/// A FEM–DEM run of days is announced by `run` with its figure, as by `check` (paused
/// at its first step here).
#[test]
fn a_run_of_days_is_announced() {
    let text = std::fs::read_to_string(example("xue2019/ring_small.toml"))
        .unwrap()
        .replace("duration = 40.0e-6", "duration = 10.0")
        .replace("every = 0.5e-6", "every = 1.0e-3");
    let (o, _dir) = run_text(&text, &[], &["--stop-at-step", "1"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let warning = o
        .stderr
        .lines()
        .find(|l| l.contains("warning"))
        .unwrap_or("");
    assert!(
        warning.contains("steps, about") && warning.contains("days"),
        "{}",
        o.stderr
    );
}
