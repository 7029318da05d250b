//! The 2D build's granular law against LAMMPS `pair_style granular` (29 Sep 2021) in
//! `dimension 2` with `fix nve/sphere disc`: see `tests/lammps/README.md` and `SPEC.md`.

use grains_dem as dem;

include!("common/lammps.rs");

#[test]
fn hertz_tsuji_mindlin_rolling_in_2d() {
    check("f1_2d_hm_tsuji_mindlin_sds");
}

#[test]
fn hooke_viscoelastic_linear_history_rolling_in_2d() {
    check("f2_2d_hooke_visco_linhist");
}
