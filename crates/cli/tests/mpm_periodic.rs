//! MPM scenarios periodic along y: a disk across the seam runs, and every value that
//! does not fit a periodic grid is refused with one line naming key and value (exit 1,
//! nothing written).

mod common;
use common::*;

const PERIODIC: &str = r#"
engine = "mpm"
name = "periodic"

[grid]
lo = [0.0, 0.0]
hi = [2.0, 2.0]
cell_size = 0.125
particles_per_cell = 2
periodic_y = 2.0

[walls]
left = { mu = 0.0 }

[[material]]
name = "elastic"
model = "linear_elastic"
density = 1.0
bulk = 1.0
shear = 0.5

[[body]]
name = "disk"
material = "elastic"
geometry = { shape = "disk", centre = [1.0, 1.9], radius = 0.4 }
velocity = [0.0, 0.2]

[run]
duration = 2.0

[output]
frames = 2
history = 20
"#;

#[test]
fn a_disk_across_the_seam_runs() {
    let (o, dir) = run_text(PERIODIC, &[], &[]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let s = summary(dir.path());
    assert_eq!(s["status"], "completed", "{s}");
}

#[test]
fn bad_periodic_values_are_refused() {
    refused_all(
        PERIODIC,
        &[
            (
                "periodic_y = 2.0",
                "periodic_y = 1.5",
                &[
                    "grid.periodic_y = 1.5",
                    "must equal the grid's height",
                    "= 2",
                ],
            ),
            (
                "geometry = { shape = \"disk\", centre = [1.0, 1.9], radius = 0.4 }",
                "geometry = { shape = \"rectangle\", lo = [0.5, -0.5], hi = [1.5, 1.75] }",
                &[
                    "body[0].geometry",
                    "spans 2.25 m along y",
                    "periodic length grid.periodic_y = 2 m",
                ],
            ),
            (
                "left = { mu = 0.0 }",
                "top = { mu = 0.0 }",
                &[
                    "walls.top",
                    "periodic along y",
                    "no wall at the bottom or top",
                ],
            ),
            (
                "name = \"periodic\"",
                "name = \"periodic\"\ngravity = [0.0, -9.8]",
                &["gravity = [0.0, -9.8]", "no y component along a periodic y"],
            ),
            (
                "hi = [2.0, 2.0]\ncell_size = 0.125\nparticles_per_cell = 2\nperiodic_y = 2.0",
                "hi = [2.0, 0.375]\ncell_size = 0.125\nparticles_per_cell = 2\nperiodic_y = 0.375",
                &[
                    "grid.periodic_y = 0.375",
                    "at least 4 cells along y; the grid has 3",
                ],
            ),
        ],
    );
}
