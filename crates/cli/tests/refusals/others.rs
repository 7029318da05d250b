//! Bad values in MPM, FEM–DEM and packing files, given to `run` and `pack`.

use super::{case, pack_edit, run_edit, Case, DEM, FEM_DEM, MPM, SPEC};

/// Bad values in MPM and FEM–DEM scenarios.
pub fn engines(all: &mut Vec<Case>) {
    let mpm: &[(&str, &str, &[&str])] = &[
        ("cell_size = 0.1", "cell_size = 0.0", &["cell_size"]),
        ("cell_size = 0.1", "cell_size = -0.1", &["cell_size"]),
        (
            "particles_per_cell = 2",
            "particles_per_cell = 0",
            &["particles_per_cell"],
        ),
        (
            "model = \"linear_elastic\"",
            "model = \"rubber\"",
            &["rubber"],
        ),
        ("density = 1.0", "density = 0.0", &["density"]),
        ("bulk = 1.0", "bulk = -1.0", &["bulk"]),
        ("material = \"soft\"", "material = \"hard\"", &["hard"]),
        ("centre = [1.0, 1.0]", "centre = [5.0, 5.0]", &["body"]),
        ("radius = 0.5", "radius = 0.0", &["radius"]),
        ("duration = 0.1", "duration = 0.0", &["duration"]),
        ("duration = 0.1", "duration = -0.1", &["duration"]),
        ("kind = \"energy_balance\"", "kind = \"vibes\"", &["vibes"]),
        ("hi = [2.0, 2.0]", "hi = [0.0, 2.0]", &["grid"]),
        ("engine = \"mpm\"", "engine = \"mpm\"\nfoo = 1", &["foo"]),
    ];
    for (from, to, expect) in mpm {
        all.push(run_edit(MPM, from, to, expect));
    }
    let fem: &[(&str, &str, &[&str])] = &[
        ("radius = 0.010", "radius = 0.0", &["charge.radius"]),
        (
            "explosive = \"tnt_llnl1985\"",
            "explosive = \"c4_homemade\"",
            &["c4_homemade"],
        ),
        ("size_edge = 0.6e-3", "size_edge = 0.0", &["size_edge"]),
        ("duration = 1.0e-6", "duration = -1.0e-6", &["duration"]),
        (
            "outer_radius = 0.030",
            "outer_radius = 0.005",
            &["outer_radius"],
        ),
        ("d0 = 0.4e-3", "d0 = 0.0", &["d0"]),
        ("material = \"quartz\"", "material = \"sand\"", &["sand"]),
        ("[charge]", "[charge]\nfoo = 1", &["foo"]),
    ];
    for (from, to, expect) in fem {
        all.push(run_edit(FEM_DEM, from, to, expect));
    }
}

/// Bad values in a packing spec.
pub fn pack(all: &mut Vec<Case>) {
    let edits: &[(&str, &str, &[&str])] = &[
        ("shape = \"annulus\"", "shape = \"hexagon\"", &["hexagon"]),
        ("r_out = 0.011", "r_out = 0.009", &["r_out"]),
        ("r_in = 0.010", "r_in = -0.010", &["r_in"]),
        ("d0 = 95.6e-6", "d0 = 0.0", &["d0"]),
        ("d0 = 95.6e-6", "d0 = nan", &["d0"]),
        ("delta = 0.177", "delta = -0.1", &["delta"]),
        (
            "distribution = \"uniform\"",
            "distribution = \"bimodal\"",
            &["bimodal"],
        ),
        (
            "target_fraction = 0.8",
            "target_fraction = 0.95",
            &["target_fraction"],
        ),
        (
            "target_fraction = 0.8",
            "target_fraction = 0.0",
            &["target_fraction"],
        ),
        ("rate = 1e-4", "rate = 0.1", &["rate"]),
        ("rate = 1e-4", "rate = 0.0", &["rate"]),
        ("seed = 1", "seed = -1", &["seed"]),
        ("seed = 1", "seed = 1\nfoo = 2", &["foo"]),
        (
            "rate = 1e-4",
            "rate = 1e-4\n[[check]]\nfigure = \"happiness\"\nat_least = 1.0",
            &["happiness"],
        ),
    ];
    for (from, to, expect) in edits {
        all.push(pack_edit(from, to, expect));
    }
    all.push(case(
        &[("s.toml", DEM)],
        &["pack", "s.toml"],
        &["grains run"],
    ));
    all.push(case(
        &[("p.toml", SPEC)],
        &["run", "p.toml"],
        &["grains pack"],
    ));
    all.push(case(
        &[("p.toml", SPEC)],
        &["check", "p.toml"],
        &["grains pack"],
    ));
}
