//! The packing file: `#` header lines with the generation parameters, then one line
//! `x y r` per disk (SI units). The DEM scenario source `source = "file"` reads it,
//! and `grains analyze` reads the `# domain = ...` and `# lining = N` lines back.

use crate::protocol::Packing;
use crate::spec::PackSpec;
use grains_analysis::sample::{DOMAIN_KEY, LINING_KEY};
use std::fmt::Write;

/// The whole file as text. Numbers are written in shortest round-trip form, so
/// reading the file gives back exactly the generated values.
pub fn packing_text(spec: &PackSpec, packing: &Packing, realised: &[(&str, f64)]) -> String {
    let mut s = String::with_capacity(packing.pos.len() * 64 + 1024);
    let _ = writeln!(s, "# grains pack: {}", spec.name);
    if !spec.description.is_empty() {
        let _ = writeln!(s, "# description: {}", spec.description.replace('\n', " "));
    }
    let _ = writeln!(
        s,
        "# generator = grains {} seed={}",
        env!("CARGO_PKG_VERSION"),
        spec.seed
    );
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
    s
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
