//! Bad values in a 3D DEM scenario (`dim = 3`), given to `run` and `check`.

use super::{check_edit, run_edit, Case};

/// A small 3D scenario that runs: one sphere just above a floor, under the granular law.
const DEM3: &str = r#"engine = "dem"
dim = 3
name = "bad3"
gravity = [0.0, 0.0, -9.81]

[domain]
lo = [0.0, 0.0, 0.0]
hi = [0.01, 0.01, 0.01]

[[material]]
name = "glass"
density = 2500.0
youngs = 48.0e9
poisson = 0.2
restitution = 0.5
friction = 0.3

[contact]
model = "granular"
normal = "hertz/material"
damping = "restitution"
tangential = "mindlin"

[[particles]]
source = "list"
material = "glass"
spheres = [{ at = [0.005, 0.005, 0.0006], radius = 0.0005 }]

[[wall]]
shape = "plane"
name = "floor"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]

[run]
duration = 1.0e-7
"#;

/// A `[pour]` table before `[run]`, with `rate` lines as given.
fn pour(rate: &str) -> String {
    format!(
        "[pour]\nmaterial = \"glass\"\nregion = {{ shape = \"box\", lo = [0.001, 0.001, 0.005], hi = [0.009, 0.009, 0.009] }}\nradius = {{ distribution = \"uniform\", min = 0.0004, max = 0.0005 }}\n{rate}count = 10\n\n[run]"
    )
}

/// A cylinder wall `tube` along `axis` round the sphere, with `release` lines as given,
/// before `[run]`.
fn tube(release: &str, axis: [f64; 3]) -> String {
    format!(
        "[[wall]]\nshape = \"cylinder\"\nname = \"tube\"\npoint = [0.005, 0.005, 0.0006]\naxis = {axis:?}\nradius = 0.004\ninside = true\n{release}\n[run]"
    )
}

/// A `runout` check on wall `wall` after `before` (which ends with `[run]`).
fn runout(wall: &str, before: &str) -> String {
    before.replace(
        "[run]",
        &format!("[[check]]\nkind = \"runout\"\nname = \"r\"\nwall = \"{wall}\"\ntolerance = 0.2\n\n[run]"),
    )
}

/// The issue's list (ν, E, e, μ, μ_r, k_r, vectors of the wrong length, overlaps at
/// the start) and the keys of the 3D schema.
pub fn values(all: &mut Vec<Case>) {
    let rolling =
        "tangential = \"mindlin\"\nrolling = \"sds\"\nkr = 10.0\ngamma_r = 0.0\nmu_r = 0.1";
    let edits: &[(&str, &str, &[&str])] = &[
        ("poisson = 0.2", "poisson = 0.5", &["poisson", "0.5"]),
        ("poisson = 0.2", "poisson = -1.0", &["poisson"]),
        ("youngs = 48.0e9", "youngs = 0.0", &["youngs"]),
        ("youngs = 48.0e9", "youngs = -48.0e9", &["youngs"]),
        ("restitution = 0.5", "restitution = 0.0", &["restitution"]),
        ("restitution = 0.5", "restitution = 1.2", &["restitution"]),
        ("friction = 0.3", "friction = -0.3", &["friction"]),
        (
            "tangential = \"mindlin\"",
            &rolling.replace("mu_r = 0.1", "mu_r = -0.1"),
            &["mu_r"],
        ),
        (
            "tangential = \"mindlin\"",
            &rolling.replace("kr = 10.0", "kr = -10.0"),
            &["kr"],
        ),
        (
            "tangential = \"mindlin\"",
            &rolling.replace("gamma_r = 0.0\n", ""),
            &["gamma_r"],
        ),
        (
            "tangential = \"mindlin\"",
            "tangential = \"mindlin\"\nrolling = \"spring\"",
            &["rolling", "spring"],
        ),
        (
            "tangential = \"mindlin\"",
            "tangential = \"mindlin\"\ntwisting = \"sds\"",
            &["twisting"],
        ),
        (
            "tangential = \"mindlin\"",
            "tangential = \"mindlin\"\nmu = -1.0",
            &["contact.mu"],
        ),
        (
            "tangential = \"mindlin\"",
            "tangential = \"mindlin\"\nkn = 1.0e6",
            &["contact.kn"],
        ),
        (
            "damping = \"restitution\"",
            "damping = \"viscoelastic\"",
            &["contact.damp"],
        ),
        (
            "damping = \"restitution\"",
            "damping = \"tsuji\"\ndamp = 0.5",
            &["contact.damp"],
        ),
        (
            "damping = \"restitution\"",
            "damping = \"hertzian\"",
            &["hertzian"],
        ),
        (
            "normal = \"hertz/material\"",
            "normal = \"hertz\"",
            &["hertz"],
        ),
        ("youngs = 48.0e9\n", "", &["youngs", "missing"]),
        (
            "model = \"granular\"",
            "model = \"hooke_history\"",
            &["normal"],
        ),
        ("model = \"granular\"", "model = \"jkr\"", &["jkr"]),
        (
            "gravity = [0.0, 0.0, -9.81]",
            "gravity = [0.0, -9.81]",
            &["gravity"],
        ),
        ("lo = [0.0, 0.0, 0.0]", "lo = [0.0, 0.0]", &["lo"]),
        (
            "at = [0.005, 0.005, 0.0006]",
            "at = [0.005, 0.0006]",
            &["at"],
        ),
        (
            "normal = [0.0, 0.0, 1.0]",
            "normal = [0.0, 1.0]",
            &["normal"],
        ),
        (
            "normal = [0.0, 0.0, 1.0]",
            "normal = [0.0, 0.0, 0.0]",
            &["normal"],
        ),
        (
            "at = [0.005, 0.005, 0.0006]",
            "at = [0.005, 0.005, 0.0001]",
            &["floor"],
        ),
        (
            "radius = 0.0005 }]",
            "radius = 0.0005 }, { at = [0.0055, 0.005, 0.0006], radius = 0.0005 }]",
            &["particles 0 and 1"],
        ),
        (
            "at = [0.005, 0.005, 0.0006]",
            "at = [0.005, 0.005, 0.02]",
            &["particle 0"],
        ),
        ("dim = 3", "dim = 4", &["dim"]),
        (
            "hi = [0.01, 0.01, 0.01]",
            "hi = [0.01, 0.01, 0.0]",
            &["domain.hi.z"],
        ),
        ("radius = 0.0005 }]", "radius = -0.0005 }]", &["radius"]),
        // Moving and bounded walls.
        (
            "normal = [0.0, 0.0, 1.0]",
            "normal = [0.0, 0.0, 1.0]\nomega = [1.0, 0.0, 0.0]",
            &["wall[0].omega", "parallel"],
        ),
        (
            "normal = [0.0, 0.0, 1.0]",
            "normal = [0.0, 0.0, 1.0]\nvelocity = [1.0, nan, 0.0]",
            &["wall[0].velocity"],
        ),
        (
            "normal = [0.0, 0.0, 1.0]",
            "normal = [0.0, 0.0, 1.0]\nvelocity = [1.0, 0.0]",
            &["velocity"],
        ),
        (
            "shape = \"plane\"\nname = \"floor\"\npoint",
            "shape = \"disk\"\nname = \"floor\"\nradius = 0.004\nhole = 0.005\ncentre",
            &["wall[0].hole", "0.005"],
        ),
        (
            "shape = \"plane\"\nname = \"floor\"\npoint",
            "shape = \"disk\"\nname = \"floor\"\nradius = -0.004\ncentre",
            &["wall[0].radius"],
        ),
        (
            "shape = \"plane\"\nname = \"floor\"\npoint",
            "shape = \"rectangle\"\nname = \"floor\"\nedge = [0.0, 0.0, 2.0]\nsize = [0.01, 0.01]\ncentre",
            &["wall[0].edge", "parallel"],
        ),
        (
            "shape = \"plane\"\nname = \"floor\"\npoint",
            "shape = \"rectangle\"\nname = \"floor\"\nedge = [1.0, 0.0, 0.0]\nsize = [0.01, 0.0]\ncentre",
            &["wall[0].size[1]"],
        ),
        (
            "shape = \"plane\"\nname = \"floor\"\npoint",
            "shape = \"rectangle\"\nname = \"floor\"\nedge = [1.0, 0.0, 0.0]\nsize = [0.01, 0.01]\nomega = [0.0, 0.0, 1.0]\ncentre",
            &["omega"],
        ),
        (
            "[run]",
            "[[check]]\nkind = \"repose_angle\"\nname = \"a\"\nwall = \"floor\"\nafter = 0.0\nlo = 20.0\nhi = 40.0\n\n[run]",
            &["check[0].wall", "cylinder"],
        ),
        (
            "[run]",
            "[[check]]\nkind = \"final_velocity\"\nname = \"v\"\nparticle = 0\ndirection = [0.0, 0.0, 0.0]\nexpected = 1.0\ntolerance = 0.01\n\n[run]",
            &["check[0].direction"],
        ),
        (
            "[run]",
            "[[check]]\nkind = \"beverloo\"\nname = \"w\"\nwall = \"floor\"\nafter = 0.0\npacking = 0.6\n\n[run]",
            &["check[0].wall", "hole"],
        ),
        // Column collapse: the tube's release and the run-out check.
        ("[run]", &tube("release = -0.1\n", [0.0, 0.0, 1.0]), &["wall[1].release", "-0.1"]),
        ("normal = [0.0, 0.0, 1.0]", "normal = [0.0, 0.0, 1.0]\nrelease = 0.1", &["release"]),
        ("[run]", &runout("floor", &tube("release = 0.1\n", [0.0, 0.0, 1.0])), &["check[0].wall", "release"]),
        ("[run]", &runout("tube", &tube("", [0.0, 0.0, 1.0])), &["check[0].wall", "release"]),
        ("[run]", &runout("tube", &tube("release = 0.1\n", [1.0, 0.0, 0.0])), &["check[0].wall", "gravity"]),
        // Pouring.
        ("[run]", &pour(""), &["pour", "exactly one"]),
        ("[run]", &pour("rate = 100.0\n").replace("count = 10\n", ""), &["pour", "count", "mass"]),
        ("[run]", &pour("rate = 100.0\nmass_rate = 0.1\n"), &["pour", "exactly one"]),
        ("[run]", &pour("rate = -100.0\n"), &["pour.rate"]),
        ("[run]", &pour("mass_rate = 0.0\n"), &["pour.mass_rate"]),
        ("[run]", &pour("rate = 100.0\n").replace("count = 10", "count = 0"), &["pour.count"]),
        ("[run]", &pour("rate = 100.0\nmass = -1.0\n"), &["pour.mass"]),
        ("[run]", &pour("rate = 100.0\n").replace("\"glass\"", "\"sand\""), &["pour.material", "sand"]),
        ("[run]", &pour("rate = 100.0\n").replace("hi = [0.009, 0.009, 0.009]", "hi = [0.009, 0.009, 0.02]"), &["pour.region", "inside the domain"]),
        ("[run]", &pour("rate = 100.0\n").replace("lo = [0.001, 0.001, 0.005]", "lo = [0.0085, 0.001, 0.005]"), &["pour.region", "largest radius"]),
        ("[run]", &pour("rate = 100.0\n").replace("min = 0.0004", "min = -0.0004"), &["pour.radius.min"]),
        ("[run]", &pour("rate = 100.0\nvelocity = [0.0, -1.0]\n"), &["velocity"]),
        ("[run]", &pour("rate = 100.0\n").replace("[run]", "[run]\nstop_kinetic_ratio = 1.0e-6"), &["run.stop_kinetic_ratio", "pour"]),
        (
            "[run]",
            "[[check]]\nkind = \"poured_mass\"\nname = \"m\"\nregion = { shape = \"box\", lo = [0.0, 0.0, 0.0], hi = [0.01, 0.01, 0.01] }\ntolerance = 1e-9\n\n[run]",
            &["check[0].kind", "pour"],
        ),
    ];
    for (from, to, expect) in edits {
        all.push(run_edit(DEM3, from, to, expect));
    }
    for (from, to, expect) in &edits[..4] {
        all.push(check_edit(DEM3, from, to, expect));
    }
    // A 2D scenario given a 3-vector.
    all.push(run_edit(
        super::DEM,
        "gravity = [0.0, -9.81]",
        "gravity = [0.0, -9.81, 0.0]",
        &["gravity"],
    ));
}
