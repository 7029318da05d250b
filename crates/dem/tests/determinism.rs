//! Results must not depend on the number of threads.

use glam::DVec2;
use grains_dem::{step, Particles, Setup, State};

/// The peer benchmark's time step.
const DT: f64 = 5e-4;

#[path = "common/peer.rs"]
mod peer;

fn bed(n: usize) -> (Setup, Particles) {
    peer::bed(n, 60)
}

fn run(threads: usize) -> State {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let (setup, p) = bed(6000);
        let mut s = State::new(&setup, p);
        for _ in 0..1000 {
            step(&setup, &mut s, DT);
        }
        s
    })
}

fn assert_same(a: &State, b: &State, what: &str) {
    let (pa, pb) = (&a.particles, &b.particles);
    assert_eq!(a.step, b.step, "{what}: step");
    assert_eq!(a.time.to_bits(), b.time.to_bits(), "{what}: time");
    assert_eq!(pa.id, pb.id, "{what}: order");
    let bits2 = |v: &[DVec2]| {
        v.iter()
            .flat_map(|x| [x.x.to_bits(), x.y.to_bits()])
            .collect::<Vec<_>>()
    };
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits2(&pa.pos), bits2(&pb.pos), "{what}: positions");
    assert_eq!(bits2(&pa.vel), bits2(&pb.vel), "{what}: velocities");
    assert_eq!(
        bits(&pa.omega),
        bits(&pb.omega),
        "{what}: angular velocities"
    );
    assert_eq!(bits2(&pa.force), bits2(&pb.force), "{what}: forces");
    assert_eq!(bits(&pa.torque), bits(&pb.torque), "{what}: torques");
    assert_eq!(a.contacts.nbr, b.contacts.nbr, "{what}: neighbour list");
    assert_eq!(
        bits(&a.contacts.shear),
        bits(&b.contacts.shear),
        "{what}: tangential history"
    );
    assert_eq!(
        bits(&a.contacts.wall_shear),
        bits(&b.contacts.wall_shear),
        "{what}: wall history"
    );
    assert_eq!(a.wall_loads, b.wall_loads, "{what}: wall loads");
}

#[test]
fn checkpoint_and_resume_is_bitwise_identical() {
    let (setup, p) = bed(3000);
    let mut straight = State::new(&setup, p.clone());
    for _ in 0..600 {
        step(&setup, &mut straight, DT);
    }
    let mut first = State::new(&setup, p);
    for _ in 0..300 {
        step(&setup, &mut first, DT);
    }
    let mut bytes = Vec::new();
    grains_dem::checkpoint::write(&first, &mut bytes).unwrap();
    drop(first);
    let mut resumed = grains_dem::checkpoint::read(&mut &bytes[..], 10_000).unwrap();
    for _ in 0..300 {
        step(&setup, &mut resumed, DT);
    }
    assert_same(&straight, &resumed, "resumed");

    // A truncated snapshot is refused, not a panic.
    for cut in [0, 7, 100, bytes.len() / 2, bytes.len() - 1] {
        assert!(
            grains_dem::checkpoint::read(&mut &bytes[..cut], 10_000).is_err(),
            "cut at {cut}"
        );
    }
    // A length field blown up by corruption is refused without allocating it.
    let mut bad = bytes.clone();
    bad[32..40].copy_from_slice(&u64::MAX.to_le_bytes());
    assert!(grains_dem::checkpoint::read(&mut &bad[..], 10_000).is_err());
}

/// One thread takes the pass and the gather in one sweep (`wavefront`), two and three
/// take them as two phases: the same bits either way.
#[test]
fn bitwise_identical_for_1_2_3_threads() {
    let a = run(1);
    assert!(
        a.contacts.builds > 1,
        "the run must rebuild its neighbour list"
    );
    for t in [2, 3] {
        assert_same(&a, &run(t), &format!("{t} threads"));
    }
}

/// Keeping the energy ledger changes nothing in the run, and its figures do not depend
/// on the thread count either.
#[test]
fn the_energy_ledger_changes_nothing() {
    let go = |threads: usize, ledger: bool| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let (setup, p) = bed(3000);
            let mut s = State::new(&setup, p);
            if ledger {
                s.ledger = Some(Default::default());
            }
            for _ in 0..500 {
                step(&setup, &mut s, DT);
            }
            s
        })
    };
    let plain = go(2, false);
    let kept = go(2, true);
    assert_same(&plain, &kept, "with the ledger");
    assert_eq!(
        grains_dem::diagnostics::state_hash(&plain),
        grains_dem::diagnostics::state_hash(&kept)
    );
    let one = go(1, true);
    let figures = grains_dem::ledger_sums::figures;
    assert_eq!(figures(&one), figures(&kept));
    let l = grains_dem::ledger_sums::figures(&kept).unwrap();
    assert!(l.damping > 0.0 && l.friction > 0.0, "{l:?}");
    // What the pass says the springs hold is what the state says.
    let (setup, _) = bed(3000);
    let now = grains_dem::EnergyLedger::starting(&setup, &kept).unwrap();
    assert!(
        (now.stored() - l.stored()).abs() <= 1e-9 * l.stored(),
        "{now:?} vs {l:?}"
    );
    assert!(l.stored_tangential > 0.0);
}

/// Particle ids are names, not indices: a run whose ids are sparse (as a rank of a
/// distributed run holds them) keeps every contact's history and is the same run, bit
/// for bit. Their order is the order of each particle's force sum (docs/parallel.md,
/// rule 1), so the renaming keeps it.
#[test]
fn ids_need_not_be_dense() {
    let (setup, p) = bed(3000);
    let mut renamed = p.clone();
    for id in renamed.id.iter_mut() {
        *id = 7 + 13 * *id;
    }
    let go = |p: Particles| {
        let mut s = State::new(&setup, p);
        for _ in 0..600 {
            step(&setup, &mut s, DT);
        }
        s
    };
    let (a, mut b) = (go(p), go(renamed));
    assert!(a.contacts.builds > 1);
    for id in b.particles.id.iter_mut() {
        *id = (*id - 7) / 13;
    }
    assert_same(&a, &b, "renamed ids");
}

/// Reductions that report two ranks but return their input, as if the other rank held
/// nothing: every global figure then goes through the distributed code path.
struct Alone;

impl grains_dem::Reduce for Alone {
    fn ranks(&self) -> usize {
        2
    }
}

impl grains_dem::Exchange for Alone {}

/// The step's global figures (rebuild test, wall loads, ledger), the measurements and
/// the hash give the serial answer when they go through the reduction interface.
#[test]
fn the_reduction_path_is_the_serial_path() {
    use grains_dem::diagnostics::{measure, measure_on, state_hash, state_hash_on};
    let (setup, p) = bed(3000);
    let mut a = State::new(&setup, p.clone());
    let mut b = State::new(&setup, p);
    a.ledger = Some(Default::default());
    b.ledger = Some(Default::default());
    for _ in 0..500 {
        step(&setup, &mut a, DT);
        grains_dem::step_on(&setup, &mut b, DT, &mut grains_dem::NoHooks, &mut Alone);
    }
    assert!(a.contacts.builds > 1);
    assert_same(&a, &b, "through the reductions");
    let figures = grains_dem::ledger_sums::figures;
    assert_eq!(figures(&a), figures(&b));
    assert_eq!(measure(&setup, &a), measure_on(&setup, &b, &Alone));
    assert_eq!(state_hash(&a), state_hash_on(&b, &Alone, |_| true));
}
