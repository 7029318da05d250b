//! The packing file: `#` header lines with the generation parameters, then one line
//! `x y r` per disk (SI units). The DEM scenario source `source = "file"` reads it,
//! and `grains analyze` reads the `# domain = ...` and `# lining = N` lines back.
//!
//! Two keys let a cached file be trusted: the first line, `# content_key = K`, is the
//! FNV-1a hash of everything after it, so an edit or a truncation shows; and
//! `# spec_key = K` names the spec that made it ([`PackSpec::key`]).

use crate::protocol::Packing;
use crate::spec::PackSpec;
use grains_analysis::sample::{DOMAIN_KEY, LINING_KEY};
use grains_core::hash::fnv1a;
use std::fmt::Write;

/// The whole file as text. Numbers are written in shortest round-trip form, so
/// reading the file gives back exactly the generated values.
pub fn packing_text(spec: &PackSpec, packing: &Packing, realised: &[(&str, f64)]) -> String {
    let mut s = String::with_capacity(packing.pos.len() * 64 + 1024);
    let _ = writeln!(s, "# grains pack: {}", spec.name);
    let _ = writeln!(s, "# {SPEC_KEY} = {:016x}", spec.key());
    provenance(&mut s, &spec.description, spec.seed);
    let _ = writeln!(s, "# {DOMAIN_KEY} = {}", packing.region.describe());
    let _ = writeln!(s, "# {LINING_KEY} = {}", packing.lining);
    let sizes = toml_inline(&spec.sizes);
    let _ = writeln!(s, "# sizes = {sizes}");
    let _ = writeln!(s, "# lining_spec = {}", toml_inline(&spec.lining));
    let _ = writeln!(s, "# protocol = {}", toml_inline(&spec.protocol));
    let realised: Vec<String> = realised.iter().map(|(k, v)| format!("{k}={v:e}")).collect();
    let _ = writeln!(s, "# realised = {}", realised.join(" "));
    let _ = writeln!(
        s,
        "# the first {} disks line the walls; columns: x y r (m)",
        packing.lining
    );
    for (p, r) in packing.pos.iter().zip(&packing.radius) {
        let _ = writeln!(s, "{:e} {:e} {:e}", p.x, p.y, r);
    }
    format!("# {CONTENT_KEY} = {:016x}\n{s}", fnv1a(s.as_bytes()))
}

/// The header lines of a packing file (2D or 3D) saying what made it: the spec's
/// description, if any, and the generator with its seed.
pub fn provenance(s: &mut String, description: &str, seed: u64) {
    if !description.is_empty() {
        let _ = writeln!(s, "# description: {}", description.replace('\n', " "));
    }
    let _ = writeln!(
        s,
        "# generator = grains {} seed={seed}",
        env!("CARGO_PKG_VERSION")
    );
}

/// Header key of the hash of the rest of the file.
pub const CONTENT_KEY: &str = "content_key";
/// Header key of the spec's key.
pub const SPEC_KEY: &str = "spec_key";

/// Why a packing file cannot be trusted as the one a spec makes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Untrusted {
    /// The file has no `# content_key` first line or no `# spec_key` line.
    NoKeys,
    /// The rest of the file does not hash to its content key: edited or truncated.
    Content {
        /// The key the file states.
        stated: u64,
        /// The hash of what the file holds.
        found: u64,
    },
    /// The file was made from another spec (or by another protocol version).
    Spec {
        /// The key the file states.
        stated: u64,
    },
}

impl std::fmt::Display for Untrusted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Untrusted::NoKeys => write!(f, "it has no {CONTENT_KEY} and {SPEC_KEY} lines"),
            Untrusted::Content { stated, found } => write!(
                f,
                "its content hashes to {found:016x}, not the {CONTENT_KEY} {stated:016x} it was written with (edited or truncated)"
            ),
            Untrusted::Spec { stated } => write!(
                f,
                "it was made from another spec or protocol version ({SPEC_KEY} {stated:016x})"
            ),
        }
    }
}

/// Checks that `text`, a whole packing file, is intact and made from the spec whose
/// key is `spec_key`.
pub fn verify(text: &str, spec_key: u64) -> Result<(), Untrusted> {
    let hex = |line: &str, key: &str| {
        let v = line.strip_prefix('#')?.trim().strip_prefix(key)?;
        u64::from_str_radix(v.trim().strip_prefix('=')?.trim(), 16).ok()
    };
    let (first, rest) = text.split_once('\n').ok_or(Untrusted::NoKeys)?;
    let stated = hex(first, CONTENT_KEY).ok_or(Untrusted::NoKeys)?;
    let found = fnv1a(rest.as_bytes());
    if found != stated {
        return Err(Untrusted::Content { stated, found });
    }
    let spec = rest
        .lines()
        .take_while(|l| l.starts_with('#'))
        .find_map(|l| hex(l, SPEC_KEY))
        .ok_or(Untrusted::NoKeys)?;
    if spec != spec_key {
        return Err(Untrusted::Spec { stated: spec });
    }
    Ok(())
}

/// A serialisable value as one-line `key = value, ...` text.
fn toml_inline<T: serde::Serialize>(v: &T) -> String {
    toml::to_string(v)
        .map(|t| {
            t.lines()
                .filter(|l| !l.trim().is_empty())
                .collect::<Vec<_>>()
                .join(", ")
        })
        .unwrap_or_default()
}
