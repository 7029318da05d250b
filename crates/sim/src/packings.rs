//! Packings on demand. A ring test names the packing spec its disks come from
//! (`[ring.packing] source = "spec"`, `spec = "packing_test2.toml"`); the first run
//! makes the packing and caches it under the spec's key, later runs reuse it.
//!
//! * The cache: `<root>/<spec name>-<key>/`, the root `runs/packings` in the current
//!   directory, or `$GRAINS_PACKINGS`. The directory holds what `grains pack` writes
//!   (packing.txt, summary.json, plots).
//! * The key ([`grains_pack::PackSpec::key`]) hashes every value that shapes the
//!   packing and the protocol's version: a changed spec gets a new directory, an
//!   unchanged one finds its file.
//! * A cached file is used only when its own keys check out
//!   ([`grains_pack::output::verify`]): an edited or truncated file is rebuilt, with a
//!   line saying why.
//! * `grains check` builds nothing: it sizes the ring from the spec
//!   ([`grains_pack::preview`]).

use crate::driver::Progress;
use grains_analysis::region::Region;
use grains_pack::output::{verify, Untrusted};
use grains_pack::preview::{preview, Preview};
use grains_pack::spec::PackSpec;
use grains_pack::Validated;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The environment variable that moves the cache.
pub const CACHE_ENV: &str = "GRAINS_PACKINGS";

/// Where cached packings live: `$GRAINS_PACKINGS`, else `runs/packings`, made absolute
/// against the current directory.
pub fn cache_root() -> PathBuf {
    let root = std::env::var_os(CACHE_ENV)
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new("runs").join("packings"));
    if root.is_absolute() {
        root
    } else {
        std::env::current_dir().unwrap_or_default().join(root)
    }
}

/// A packing spec a scenario names, and where its packing is cached.
#[derive(Clone, Debug)]
pub struct OnDemand {
    /// The spec file.
    pub path: PathBuf,
    /// The spec.
    pub spec: PackSpec,
    /// Its text (copied next to the packing).
    pub text: String,
    /// What follows from it.
    pub validated: Validated,
    /// Its key.
    pub key: u64,
    /// The cache directory of this key.
    pub dir: PathBuf,
}

/// The state of a packing in the cache.
#[derive(Clone, Debug, PartialEq)]
pub enum Cached {
    /// Made, intact and from this spec.
    Ready,
    /// Not made yet.
    Missing,
    /// There is a file, but it cannot be trusted.
    Untrusted(Untrusted),
}

impl OnDemand {
    /// Reads and validates the spec at `path`; errors name `key` (the scenario's key
    /// that names the spec) and are one line.
    pub fn open(path: &Path, key: &str) -> Result<Self, String> {
        let shown = path.display();
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("{key} = \"{shown}\": cannot read the packing spec: {e}"))?;
        let spec = grains_pack::parse(&text, &shown.to_string())
            .map_err(|e| format!("{key} = \"{shown}\": {e}"))?;
        let validated =
            grains_pack::validate(&spec).map_err(|e| format!("{key} = \"{shown}\": {e}"))?;
        let k = spec.key();
        let dir = cache_root().join(format!("{}-{k:016x}", spec.name));
        Ok(OnDemand {
            path: path.to_path_buf(),
            spec,
            text,
            validated,
            key: k,
            dir,
        })
    }

    /// The cached packing file.
    pub fn file(&self) -> PathBuf {
        self.dir.join("packing.txt")
    }

    /// Whether the packing is made and can be used.
    pub fn state(&self) -> Cached {
        match std::fs::read_to_string(self.file()) {
            Err(_) => Cached::Missing,
            Ok(text) => match verify(&text, self.key) {
                Ok(()) => Cached::Ready,
                Err(u) => Cached::Untrusted(u),
            },
        }
    }

    /// The disks the spec will make, without making them (lattice starts only).
    pub fn preview(&self) -> Option<Preview> {
        preview(&self.spec, &self.validated)
    }

    /// Makes the packing unless it is cached and intact; returns its file. Progress
    /// goes to `progress`, the protocol's stage lines to `pack.log` beside the file.
    pub fn ensure(&self, progress: &mut dyn Progress) -> Result<PathBuf, String> {
        let why = match self.state() {
            Cached::Ready => return Ok(self.file()),
            Cached::Missing => "not made yet".to_string(),
            Cached::Untrusted(u) => {
                format!("the cached {} cannot be used: {u}", self.file().display())
            }
        };
        progress.announce(&format!(
            "packing {} ({}): {why}; making it (about {:.0} disks) → {}",
            self.spec.name,
            self.path.display(),
            self.validated.estimated_particles,
            self.dir.display()
        ));
        std::fs::create_dir_all(&self.dir)
            .map_err(|e| format!("cannot create {}: {e}", self.dir.display()))?;
        let mut log = String::new();
        let started = Instant::now();
        let mut watch = Watcher {
            progress,
            log: &mut log,
            what: format!("packing {}", self.spec.name),
        };
        let made = crate::pack::pack(
            &self.spec,
            &self.text,
            &self.validated,
            &self.dir,
            &mut watch,
        );
        let _ = std::fs::write(self.dir.join("pack.log"), &log);
        let made = made.map_err(|e| format!("packing {}: {e:#}", self.spec.name))?;
        progress.finish();
        let failed: Vec<&str> = made
            .checks
            .iter()
            .filter(|c| !c.pass)
            .map(|c| c.name.as_str())
            .collect();
        progress.announce(&format!(
            "packing {} made in {:.0} s{}",
            self.spec.name,
            started.elapsed().as_secs_f64(),
            if failed.is_empty() {
                String::new()
            } else {
                format!(
                    "; its own checks failed ({}; see {}/summary.json)",
                    failed.join(", "),
                    self.dir.display()
                )
            }
        ));
        match self.state() {
            Cached::Ready => Ok(self.file()),
            Cached::Missing => Err(format!("{}: not written", self.file().display())),
            Cached::Untrusted(u) => Err(format!("{}: {u}", self.file().display())),
        }
    }

    /// Refuses a spec whose domain is not the annulus `r_in`–`r_out` about `centre`.
    pub fn fits_ring(
        &self,
        key: &str,
        r_in: f64,
        r_out: f64,
        centre: [f64; 2],
    ) -> Result<(), String> {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * r_out.abs();
        let annulus = |a: f64, b: f64, c: [f64; 2]| {
            format!(
                "the annulus r_in = {a} m, r_out = {b} m about ({}, {})",
                c[0], c[1]
            )
        };
        let found = match self.validated.region {
            Region::Annulus {
                centre: c,
                r_in: a,
                r_out: b,
            } => {
                if close(a, r_in)
                    && close(b, r_out)
                    && close(c.x, centre[0])
                    && close(c.y, centre[1])
                {
                    return Ok(());
                }
                annulus(a, b, [c.x, c.y])
            }
            Region::Disk { radius, .. } => format!("a disk of radius {radius} m"),
            Region::Rectangle { lo, hi, .. } => {
                format!("a rectangle {} m × {} m", hi.x - lo.x, hi.y - lo.y)
            }
        };
        Err(format!(
            "{key} = \"{}\": the spec packs {found}; it must pack the ring's, {}",
            self.path.display(),
            annulus(r_in, r_out, centre)
        ))
    }
}

/// The protocol's report, turned into a progress bar and a log.
struct Watcher<'a> {
    progress: &'a mut dyn Progress,
    log: &'a mut String,
    what: String,
}

impl grains_pack::Watch for Watcher<'_> {
    fn line(&mut self, line: String) {
        self.log.push_str(&line);
        self.log.push('\n');
    }

    fn progress(&mut self, done: f64) {
        self.progress.stage(&self.what, done);
    }
}
