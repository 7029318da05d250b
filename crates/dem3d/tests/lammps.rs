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

mod hooke {
    use grains_dem3d as dem;

    include!("../../dem/tests/common/lammps_hooke.rs");

    fn floor() -> dem::WallShape {
        dem::WallShape::Plane {
            point: [0.0; 3],
            normal: [0.0, 0.0, 1.0],
        }
    }

    #[test]
    fn two_spheres_stick_and_slip() {
        check("h1_two_spheres", 1e-10);
    }

    #[test]
    fn two_spheres_sliding() {
        check("h1s_two_spheres_slide", 1e-10);
    }

    #[test]
    fn three_spheres_two_contacts_at_once() {
        check("h2_three_triangle", 1e-10);
    }

    #[test]
    fn a_sphere_on_a_wall() {
        check("h3_wall", 1e-10);
    }
}
