//! A charge written to a snapshot mid-detonation and read back goes on bitwise as the
//! original does; a snapshot of another mesh, or a cut one, is refused.

use glam::DVec2;
use grains_fem::diagnostics::state_hash;
use grains_fem::{
    checkpoint, mesh, step, Burn, Charge, Explosive, FemSetup, Mesh, MeshSpec, Viscosity,
};

fn setup() -> FemSetup {
    FemSetup::new(
        Explosive::built_in("tnt").unwrap(),
        "charge",
        DVec2::ZERO,
        0.005,
        Burn::default(),
        Viscosity::default(),
        None,
        0.0,
        0.5,
    )
    .unwrap()
}

fn charge_mesh(size: f64) -> Mesh {
    mesh::circle(
        0.005,
        DVec2::ZERO,
        &MeshSpec {
            size_centre: size,
            size_edge: size,
            grading: 0.25,
        },
    )
    .unwrap()
}

fn advance(s: &FemSetup, c: &mut Charge, steps: usize) {
    for _ in 0..steps {
        let dt = c.next_dt(s);
        step(s, c, dt).unwrap();
    }
}

#[test]
fn a_charge_read_back_goes_on_bitwise() {
    let s = setup();
    let m = charge_mesh(0.4e-3);
    let mut a = Charge::new(&s, &m);
    advance(&s, &mut a, 60);
    let mut bytes = Vec::new();
    checkpoint::write(&a, &mut bytes).unwrap();
    let mut b = Charge::new(&s, &m);
    checkpoint::read_into(&mut b, &mut bytes.as_slice()).unwrap();
    assert_eq!(state_hash(&a), state_hash(&b));
    advance(&s, &mut a, 60);
    advance(&s, &mut b, 60);
    assert_eq!(a.step, 120);
    assert_eq!(
        state_hash(&a),
        state_hash(&b),
        "the read-back charge drifted"
    );

    let mut other = Charge::new(&s, &charge_mesh(0.5e-3));
    let e = checkpoint::read_into(&mut other, &mut bytes.as_slice()).unwrap_err();
    assert!(e.to_string().contains("nodes"), "{e}");
    let mut cut = Charge::new(&s, &m);
    let e = checkpoint::read_into(&mut cut, &mut &bytes[..bytes.len() - 100]).unwrap_err();
    assert!(e.to_string().contains("truncated"), "{e}");
}
