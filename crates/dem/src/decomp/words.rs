//! A particle as the words a message carries: every field, bit for bit (its running
//! energy ledger too, when it is kept), and for a particle changing rank its wall
//! springs and its (partner id, spring) rows (the granular law's whole histories
//! likewise).

use crate::history::GranularHistory;
use crate::math::{AngVector, Components, Tangent, Vector};
use crate::particles::Particles;

/// Words as little-endian bytes.
pub fn bytes_of(words: &[u64]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

/// Little-endian bytes as words.
pub fn words_of(bytes: &[u8]) -> Vec<u64> {
    bytes
        .chunks_exact(8)
        .map(|c| u64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect()
}

/// Appends components as their bits.
fn put<C: Components>(out: &mut Vec<u64>, v: C) {
    out.extend((0..C::N).map(|a| v.get(a).to_bits()));
}

/// Reads words in order.
pub struct Reader<'a> {
    words: &'a [u64],
    at: usize,
}

impl<'a> Reader<'a> {
    /// Reads `words` from the start.
    pub fn new(words: &'a [u64]) -> Self {
        Reader { words, at: 0 }
    }

    /// Whether every word has been read.
    pub fn done(&self) -> bool {
        self.at >= self.words.len()
    }

    /// The next word.
    pub fn word(&mut self) -> u64 {
        self.at += 1;
        self.words[self.at - 1]
    }

    fn f64(&mut self) -> f64 {
        f64::from_bits(self.word())
    }

    fn get<C: Components>(&mut self) -> C {
        let c: Vec<f64> = (0..C::N).map(|_| self.f64()).collect();
        C::from_slice(&c)
    }
}

/// Appends particle `i`'s every field; its running ledger, if it has one, only with
/// `ledger` (a ghost's is never summed: it gets an empty one).
pub fn put_particle(out: &mut Vec<u64>, p: &Particles, i: usize, ledger: bool) {
    out.push(p.id[i] as u64);
    put(out, p.pos[i]);
    put(out, p.vel[i]);
    put(out, p.omega[i]);
    out.push(p.radius[i].to_bits());
    out.push(p.inv_mass[i].to_bits());
    out.push(p.inv_inertia[i].to_bits());
    // The material's word also says whether the ledger is kept and the row follows.
    let row = p.ledger.get(i);
    let flags =
        (row.is_some() as u64) << LEDGER_KEPT | ((ledger && row.is_some()) as u64) << ROW_SENT;
    out.push(p.material[i] as u64 | flags);
    put(out, p.force[i]);
    put(out, p.torque[i]);
    if let Some(row) = row.filter(|_| ledger) {
        out.extend(row.iter().map(|x| x.to_bits()));
    }
}

/// The bits of [`put_particle`]'s material word saying that the energy ledger is kept
/// and that the particle's running ledger follows.
const LEDGER_KEPT: u32 = 32;
const ROW_SENT: u32 = 33;

/// Reads one particle written by [`put_particle`] onto the end of `p`.
pub fn get_particle(r: &mut Reader, p: &mut Particles) {
    p.id.push(r.word() as u32);
    p.pos.push(r.get());
    p.vel.push(r.get());
    p.omega.push(r.get());
    p.radius.push(r.f64());
    p.inv_mass.push(r.f64());
    p.inv_inertia.push(r.f64());
    let material = r.word();
    p.material.push(material as u16);
    p.force.push(r.get());
    p.torque.push(r.get());
    if material >> ROW_SENT & 1 == 1 {
        let row = std::array::from_fn(|_| r.f64());
        p.ledger.push(row);
    } else if material >> LEDGER_KEPT & 1 == 1 {
        p.ledger.push(Default::default());
    }
}

/// Appends particle `i` of `p` to `out`, every field.
pub fn copy_particle(p: &Particles, i: usize, out: &mut Particles) {
    out.id.push(p.id[i]);
    out.pos.push(p.pos[i]);
    out.vel.push(p.vel[i]);
    out.omega.push(p.omega[i]);
    out.radius.push(p.radius[i]);
    out.inv_mass.push(p.inv_mass[i]);
    out.inv_inertia.push(p.inv_inertia[i]);
    out.material.push(p.material[i]);
    out.force.push(p.force[i]);
    out.torque.push(p.torque[i]);
    if let Some(row) = p.ledger.get(i) {
        out.ledger.push(*row);
    }
}

/// Words [`put_motion`] writes per particle.
pub const MOTION_WORDS: usize = 3 * Vector::N + 2 * AngVector::N;

/// Appends what changes every step: position, velocity, spin, force, torque.
pub fn put_motion(out: &mut Vec<u64>, p: &Particles, i: usize) {
    put(out, p.pos[i]);
    put(out, p.vel[i]);
    put(out, p.omega[i]);
    put(out, p.force[i]);
    put(out, p.torque[i]);
}

/// Reads what [`put_motion`] wrote into particle `i`.
pub fn get_motion(r: &mut Reader, p: &mut Particles, i: usize) {
    p.pos[i] = r.get::<Vector>();
    p.vel[i] = r.get::<Vector>();
    p.omega[i] = r.get::<AngVector>();
    p.force[i] = r.get::<Vector>();
    p.torque[i] = r.get::<AngVector>();
}

/// A particle's contact history, which goes with it to another rank: its wall springs
/// and its pair springs as (partner id, spring as seen from it), under the linear law;
/// the same as whole histories under the granular law (the other pair empty).
#[derive(Clone, Debug, Default)]
pub struct Carried {
    /// The linear law's spring with each wall.
    pub walls: Vec<Tangent>,
    /// The linear law's springs with other particles.
    pub rows: Vec<(u32, Tangent)>,
    /// The granular law's history with each wall (empty under the linear law).
    pub granular_walls: Vec<GranularHistory>,
    /// The granular law's histories with other particles.
    pub granular_rows: Vec<(u32, GranularHistory)>,
}

/// Appends a particle's contact history: its wall springs, then the number of its
/// springs and each as (partner id, spring as seen from it); then the number of its
/// granular wall histories and each, and the same for its granular pair histories.
pub fn put_history(out: &mut Vec<u64>, c: &Carried) {
    for &w in &c.walls {
        put(out, w);
    }
    out.push(c.rows.len() as u64);
    for &(j, xi) in &c.rows {
        out.push(j as u64);
        put(out, xi);
    }
    out.push(c.granular_walls.len() as u64);
    for h in &c.granular_walls {
        out.extend(h.iter().map(|x| x.to_bits()));
    }
    out.push(c.granular_rows.len() as u64);
    for (j, h) in &c.granular_rows {
        out.push(*j as u64);
        out.extend(h.iter().map(|x| x.to_bits()));
    }
}

/// Reads what [`put_history`] wrote, for `walls` walls.
pub fn get_history(r: &mut Reader, walls: usize) -> Carried {
    let walls = (0..walls).map(|_| r.get()).collect();
    let n = r.word() as usize;
    let rows = (0..n).map(|_| (r.word() as u32, r.get())).collect();
    let history = |r: &mut Reader| -> GranularHistory { std::array::from_fn(|_| r.f64()) };
    let n = r.word() as usize;
    let granular_walls = (0..n).map(|_| history(r)).collect();
    let n = r.word() as usize;
    let granular_rows = (0..n).map(|_| (r.word() as u32, history(r))).collect();
    Carried {
        walls,
        rows,
        granular_walls,
        granular_rows,
    }
}
