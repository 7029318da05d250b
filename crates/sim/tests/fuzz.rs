//! Property tests standing in for fuzz targets (cargo fuzz needs a nightly compiler):
//! the scenario reader of every engine, the packing-spec reader and the checkpoint
//! reader are fed the examples (the corpus: every `.toml` under `examples/`) with
//! random mutations, and must answer every input with a value or an error, never a
//! panic. Each property is bounded by its case count so the whole file takes seconds.
//! Cases proptest shrinks to on a failure are kept in `proptest-regressions/` and
//! replayed first; the crashes found so far are regression tests at the end.

use grains_sim::scenario::{self, FileKind};
use grains_sim::Source;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use std::path::{Path, PathBuf};

/// `cases` cases from a fixed seed, so that CI sees the same inputs every run; set
/// `PROPTEST_RNG_SEED` (and `PROPTEST_CASES`) to explore further.
fn config(cases: u32) -> Config {
    let mut c = Config::default();
    if std::env::var_os("PROPTEST_CASES").is_none() {
        c.cases = cases;
    }
    if std::env::var_os("PROPTEST_RNG_SEED").is_none() {
        c.rng_seed = RngSeed::Fixed(27);
    }
    c
}

/// Every example file: the corpus the mutations start from.
fn corpus() -> Vec<(PathBuf, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut out = Vec::new();
    let mut todo = vec![root];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                todo.push(p);
            } else if p.extension().is_some_and(|x| x == "toml") {
                let text = std::fs::read_to_string(&p).unwrap();
                out.push((p, text));
            }
        }
    }
    out.sort();
    assert!(out.len() >= 30, "the corpus lost its examples");
    out
}

/// Values that sit on or past the edge of what a key allows.
const NASTY: &[&str] = &[
    "0",
    "-0.0",
    "-1",
    "1",
    "2",
    "0.5",
    "1e308",
    "-1e308",
    "5e-324",
    "nan",
    "inf",
    "-inf",
    "1e9",
    "4294967296",
    "18446744073709551615",
    "-9223372036854775808",
    "\"\"",
    "\"../x\"",
    "[]",
    "[0.0]",
    "[nan, nan]",
    "{}",
    "true",
];

/// Lines a user might add by mistake.
const LINES: &[&str] = &[
    "dt = 1e-12",
    "safety = 0.5",
    "engine = \"mpm\"",
    "engine = \"fem_dem\"",
    "[run]",
    "[output]\nframes = 0",
    "[[check]]\nkind = \"energy_balance\"\nname = \"x\"\nmax = 0.1",
    "[[wall]]\nname = \"w\"\nshape = \"segment\"\na = [0.0, 0.0]\nb = [0.0, 0.0]",
    "[sizes]\ndistribution = \"gaussian\"\nd0 = 0.0\ndelta = 0.1",
    "periodic = [true, true]",
    "count = 0",
];

/// One edit of a scenario's text.
#[derive(Clone, Debug)]
enum Edit {
    /// The k-th number in the text becomes a nasty value.
    Number(usize, usize),
    /// The k-th line is removed.
    Drop(usize),
    /// The k-th line is repeated.
    Repeat(usize),
    /// A line is inserted before the k-th.
    Insert(usize, usize),
    /// The byte at k becomes b.
    Byte(usize, u8),
    /// The text is cut at k.
    Cut(usize),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        4 => (any::<usize>(), 0..NASTY.len()).prop_map(|(k, v)| Edit::Number(k, v)),
        1 => any::<usize>().prop_map(Edit::Drop),
        1 => any::<usize>().prop_map(Edit::Repeat),
        1 => (any::<usize>(), 0..LINES.len()).prop_map(|(k, v)| Edit::Insert(k, v)),
        1 => (any::<usize>(), any::<u8>()).prop_map(|(k, b)| Edit::Byte(k, b)),
        1 => any::<usize>().prop_map(Edit::Cut),
    ]
}

/// Where the numbers of `text` are: digit runs with their sign, dots and exponents.
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts = b[i].is_ascii_digit() && (i == 0 || !b[i - 1].is_ascii_alphanumeric());
        if starts {
            let lo = if i > 0 && b[i - 1] == b'-' { i - 1 } else { i };
            let mut j = i;
            while j < b.len() && (b[j].is_ascii_alphanumeric() || b"._+-".contains(&b[j])) {
                j += 1;
            }
            out.push((lo, j));
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

fn apply(text: &str, e: &Edit) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let n = lines.len().max(1);
    match *e {
        Edit::Number(k, v) => {
            let spots = numbers(text);
            if spots.is_empty() {
                return text.to_string();
            }
            let (lo, hi) = spots[k % spots.len()];
            format!("{}{}{}", &text[..lo], NASTY[v], &text[hi..])
        }
        Edit::Drop(k) => {
            let mut l = lines.clone();
            if !l.is_empty() {
                l.remove(k % n);
            }
            l.join("\n")
        }
        Edit::Repeat(k) => {
            let mut l = lines.clone();
            if !l.is_empty() {
                let line = l[k % n];
                l.insert(k % n, line);
            }
            l.join("\n")
        }
        Edit::Insert(k, v) => {
            let mut l = lines.clone();
            l.insert(k % (l.len() + 1), LINES[v]);
            l.join("\n")
        }
        Edit::Byte(k, b) => {
            let mut bytes = text.as_bytes().to_vec();
            if !bytes.is_empty() {
                let at = k % bytes.len();
                bytes[at] = b;
            }
            String::from_utf8_lossy(&bytes).into_owned()
        }
        Edit::Cut(k) => {
            let at = k % (text.len() + 1);
            String::from_utf8_lossy(&text.as_bytes()[..at]).into_owned()
        }
    }
}

/// Reads `text` as `grains run` and `grains pack` would: the file kind, then the
/// scenario (every engine) or the packing spec with its validation.
fn read_as_user(text: &str, base: &Path) {
    match scenario::kind_of(text, "fuzz.toml") {
        Ok(FileKind::PackingSpec) => {
            if let Ok(spec) = grains_pack::parse(text, "fuzz.toml") {
                let _ = grains_pack::validate(&spec);
            }
        }
        Ok(FileKind::Scenario) => {
            let src = Source {
                text: text.to_string(),
                origin: "fuzz.toml".into(),
                base: base.to_path_buf(),
            };
            let _ = scenario::parse(&src);
        }
        Err(_) => {}
    }
}

proptest! {
    #![proptest_config(config(1024))]

    /// Every example, edited up to four times, is read or refused without a panic.
    #[test]
    fn scenario_and_spec_readers_never_panic(
        pick in any::<usize>(),
        edits in prop::collection::vec(edit(), 1..5),
    ) {
        let all = corpus_cached();
        let (path, text) = &all[pick % all.len()];
        let mut t = text.clone();
        for e in &edits {
            t = apply(&t, e);
        }
        read_as_user(&t, path.parent().unwrap());
    }
}

/// The small examples whose full validation (`grains check`: assembly, step, memory)
/// takes milliseconds, so that it can run hundreds of times.
const CHECKED: &[&str] = &[
    "dem/head_on.toml",
    "dem/oblique_impact.toml",
    "dem3d/chung_ooi_test2.toml",
    "mpm/j2_simple_shear.toml",
    "mpm/maxwell_relaxation.toml",
    "mpm/thermal_free_expansion.toml",
];

proptest! {
    #![proptest_config(config(384))]

    /// `grains check` of a small example with its numbers replaced by edge values:
    /// figures or a refusal, never a panic.
    #[test]
    fn check_never_panics(
        pick in 0..CHECKED.len(),
        edits in prop::collection::vec(
            (any::<usize>(), 0..NASTY.len()).prop_map(|(k, v)| Edit::Number(k, v)),
            1..4,
        ),
    ) {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples").join(CHECKED[pick]);
        let mut t = std::fs::read_to_string(&path).unwrap();
        for e in &edits {
            t = apply(&t, e);
        }
        if std::env::var_os("FUZZ_SHOW").is_some() {
            eprintln!("---- {}\n{t}", CHECKED[pick]);
        }
        let src = Source { text: t, origin: "fuzz.toml".into(), base: path.parent().unwrap().into() };
        let _ = grains_sim::check::check(&src, 1);
    }
}

fn corpus_cached() -> &'static [(PathBuf, String)] {
    static C: std::sync::OnceLock<Vec<(PathBuf, String)>> = std::sync::OnceLock::new();
    C.get_or_init(corpus)
}

/// A real checkpoint of `examples/dem/head_on.toml` (a DEM state written by the engine,
/// sealed by the run loop), with its scenario and the directory it lies in.
struct Saved {
    dir: tempfile::TempDir,
    text: String,
    file: Vec<u8>,
}

fn saved() -> &'static Saved {
    static S: std::sync::OnceLock<Saved> = std::sync::OnceLock::new();
    S.get_or_init(|| {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/dem/head_on.toml");
        let src = Source::read(&path).unwrap();
        let scenario::Scenario::Dem(s) = scenario::parse(&src).unwrap() else {
            panic!("not dem")
        };
        let a = grains_sim::dem::assemble::assemble(&s, &src.base).unwrap();
        let mut state = grains_dem::State::new(&a.setup, a.particles);
        for _ in 0..10 {
            grains_dem::step(&a.setup, &mut state, a.dt);
        }
        let mut bytes = Vec::new();
        grains_dem::checkpoint::write(&state, &mut bytes).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join(grains_sim::checkpoint::FILE);
        grains_sim::checkpoint::save(&file, &src.text, &bytes, &Default::default()).unwrap();
        Saved {
            file: std::fs::read(&file).unwrap(),
            dir,
            text: src.text,
        }
    })
}

/// One change to a checkpoint's bytes.
#[derive(Clone, Debug)]
enum Damage {
    /// The byte at k is xor-ed with b (b ≠ 0).
    Flip(usize, u8),
    /// The 8 bytes at k become the little-endian word w (a length, a count).
    Word(usize, u64),
    /// The file is cut at k.
    Cut(usize),
    /// n bytes of b are added at the end.
    Grow(usize, u8),
}

fn damage() -> impl Strategy<Value = Damage> {
    let word = prop_oneof![
        Just(0u64),
        Just(1),
        Just(u32::MAX as u64),
        Just(u64::MAX),
        Just(1 << 31),
        0u64..5000,
        any::<u64>(),
    ];
    prop_oneof![
        3 => (any::<usize>(), 1u8..=255).prop_map(|(k, b)| Damage::Flip(k, b)),
        3 => (any::<usize>(), word).prop_map(|(k, w)| Damage::Word(k, w)),
        1 => any::<usize>().prop_map(Damage::Cut),
        1 => (0usize..64, any::<u8>()).prop_map(|(n, b)| Damage::Grow(n, b)),
    ]
}

fn hurt(bytes: &mut Vec<u8>, d: &Damage) {
    let n = bytes.len().max(1);
    match *d {
        Damage::Flip(k, b) => {
            if let Some(x) = bytes.get_mut(k % n) {
                *x ^= b;
            }
        }
        Damage::Word(k, w) => {
            let at = k % n;
            for (i, b) in w.to_le_bytes().iter().enumerate() {
                if let Some(x) = bytes.get_mut(at + i) {
                    *x = *b;
                }
            }
        }
        Damage::Cut(k) => bytes.truncate(k % (bytes.len() + 1)),
        Damage::Grow(m, b) => bytes.extend(std::iter::repeat_n(b, m)),
    }
}

/// Loads `bytes` as `grains resume` would, in a directory of its own: whether it was
/// read.
fn resume_from(bytes: &[u8]) -> bool {
    let s = saved();
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join(grains_sim::checkpoint::FILE), bytes).unwrap();
    let src = Source {
        text: s.text.clone(),
        origin: "head_on.toml".into(),
        base: Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/dem"),
    };
    let scenario::Scenario::Dem(scn) = scenario::parse(&src).unwrap() else {
        unreachable!()
    };
    grains_sim::dem::run::load_checkpoint(&scn, &src, dir.path()).is_ok()
}

proptest! {
    #![proptest_config(config(384))]

    /// A damaged checkpoint, its checksum left as it was: refused, never a panic.
    #[test]
    fn damaged_checkpoints_are_refused(ds in prop::collection::vec(damage(), 1..4)) {
        let mut b = saved().file.clone();
        for d in &ds {
            hurt(&mut b, d);
        }
        resume_from(&b);
    }

    /// A damaged checkpoint resealed with a valid checksum, so the damage reaches the
    /// header, the run's progress and the engine's arrays: refused or read, never a
    /// panic and never an allocation the file's size cannot back.
    #[test]
    fn resealed_checkpoints_never_panic(ds in prop::collection::vec(damage(), 1..4)) {
        let s = saved();
        let mut b = s.file[..s.file.len() - 8].to_vec();
        for d in &ds {
            hurt(&mut b, d);
        }
        let sum = grains_core::hash::fnv1a(&b);
        b.extend_from_slice(&sum.to_le_bytes());
        resume_from(&b);
    }
}

/// The undamaged checkpoint reads back: the properties above start from a valid file.
#[test]
fn the_seed_checkpoint_reads() {
    assert!(saved().dir.path().exists());
    assert!(resume_from(&saved().file));
}

/// Found by `check_never_panics`: a body reaching to y = -1e308 was filled point by
/// point (forever, gigabytes) before its points were found outside the grid.
#[test]
fn a_body_far_outside_the_grid_is_refused_at_once() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/mpm/j2_simple_shear.toml");
    let text = std::fs::read_to_string(&path).unwrap().replacen(
        "lo = [0.0, 0.0], hi = [6.0, 1.0]",
        "lo = [0.0, -1e308], hi = [6.0, 1.0]",
        1,
    );
    assert!(text.contains("-1e308"));
    let src = Source {
        text,
        origin: "s.toml".into(),
        base: path.parent().unwrap().into(),
    };
    let Err(e) = grains_sim::check::check(&src, 1) else {
        panic!("accepted")
    };
    assert!(
        e.contains("body[0].geometry") && e.contains("inside the grid"),
        "{e}"
    );
}
