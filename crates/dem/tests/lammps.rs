//! The 2D build's granular law against LAMMPS `pair_style granular` (29 Sep 2021) in
//! `dimension 2` with `fix nve/sphere disc`: see `tests/lammps/README.md` and `SPEC.md`.

use grains_dem as dem;

include!("common/lammps.rs");

#[test]
fn hertz_tsuji_mindlin_rolling_in_2d() {
    check("f1_2d_hm_tsuji_mindlin_sds");
}

#[test]
fn three_disks_two_types_in_2d() {
    check("f3_2d_three_disks_two_types");
}

#[test]
fn hooke_viscoelastic_linear_history_rolling_in_2d() {
    check("f2_2d_hooke_visco_linhist");
}

mod hooke {
    use grains_dem as dem;

    include!("common/lammps_hooke.rs");

    /// No 2D deck has a wall.
    fn floor() -> dem::WallShape {
        unreachable!("no 2D deck has a wall")
    }

    /// The 2D spring is a component along t = (−n_y, n_x), so it keeps its length as
    /// the normal turns (as `pair granular` does); `gran/hooke/history` projects its
    /// vector onto the new tangent plane, shortening it by cos Δθ each step. On this deck
    /// that is 5.0e-7 of a field; a Python copy of `gran/hooke/history` with that one
    /// change (the length kept) is 5.4e-7 from LAMMPS (`tests/lammps/hooke/README.md`).
    #[test]
    fn two_disks() {
        check("h4_2d_disks", 1e-6);
    }
}
