//! The 3D build's granular law against LAMMPS `pair_style granular` (29 Sep 2021) on two-
//! and three-sphere decks: see `crates/dem/tests/lammps/README.md` and `SPEC.md`.

use grains_dem3d as dem;

include!("../../dem/tests/common/lammps.rs");

#[test]
fn hertz_tsuji_mindlin_rolling_twisting() {
    check("a_hm_tsuji_mindlin_sds_marshall");
}

#[test]
fn hertz_mindlin_rescale() {
    check("b_hm_tsuji_mindlinrescale_sds_marshall");
}

#[test]
fn hooke_viscoelastic_linear_history_rolling_twisting() {
    check("c1_hooke_visco_linhist_sds_marshall");
}

#[test]
fn hooke_velocity_damping_linear_history() {
    check("c2_hooke_velocity_linhist");
}

#[test]
fn three_spheres_two_materials() {
    check("d_three_row_two_types");
}

#[test]
fn limit_damping() {
    check("g_hm_tsuji_mindlin_sds_marshall_limitdamping");
}
